#!/usr/bin/env python3
"""Writes a binary STL of a UV sphere (the slicing benchmark's part): make_sphere_stl.py OUT [RADIUS_MM] [SEGMENTS]."""
import math
import struct
import sys

out = sys.argv[1]
radius = float(sys.argv[2]) if len(sys.argv) > 2 else 200.0
nu = int(sys.argv[3]) if len(sys.argv) > 3 else 192
nv = nu // 2
centre = (radius + 50.0, radius + 50.0, radius)


def point(i, j):
    theta = math.pi * j / nv
    phi = 2 * math.pi * i / nu
    return (centre[0] + radius * math.sin(theta) * math.cos(phi),
            centre[1] + radius * math.sin(theta) * math.sin(phi),
            centre[2] - radius * math.cos(theta))


triangles = []
for j in range(nv):
    for i in range(nu):
        a, b, c, d = point(i, j), point(i + 1, j), point(i + 1, j + 1), point(i, j + 1)
        if j > 0:
            triangles.append((a, b, c))
        if j < nv - 1:
            triangles.append((a, c, d))
with open(out, "wb") as f:
    f.write(b"\0" * 80)
    f.write(struct.pack("<I", len(triangles)))
    for t in triangles:
        f.write(struct.pack("<3f", 0.0, 0.0, 0.0))
        for v in t:
            f.write(struct.pack("<3f", *v))
        f.write(b"\0\0")
print(f"{out}: {len(triangles)} triangles, radius {radius} mm")
