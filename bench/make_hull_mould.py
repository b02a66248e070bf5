#!/usr/bin/env python3
"""Writes a binary STL of an LSAM-scale hull-mould shell (the deposition benchmark's part):
make_hull_mould.py OUT [LENGTH_MM WIDTH_MM HEIGHT_MM WALL_MM].

An open-top tub whose horizontal sections are rounded rectangles (superellipses, exponent 4) that flare
from 80 % of the top's size at the bottom to the full size at the top, like the female mould of a boat
hull; the wall and the floor are WALL_MM thick (two 0.83 in LSAM beads by default). Closed and
outward-facing."""
import math
import struct
import sys

out = sys.argv[1]
length, width, height, wall = (float(v) for v in (sys.argv[2:6] if len(sys.argv) >= 6 else (1500, 600, 500, 41)))
segments, rings = 160, 40
cx, cy = length / 2 + 50, width / 2 + 50


def semi_axes(z):
    t = (z / height) ** 0.7
    return (0.8 + 0.2 * t) * length / 2, (0.8 + 0.2 * t) * width / 2


def ring(z, inset):
    a, b = semi_axes(z)
    a, b = a - inset, b - inset
    pts = []
    for i in range(segments):
        phi = 2 * math.pi * i / segments
        c, s = math.cos(phi), math.sin(phi)
        pts.append((cx + a * math.copysign(abs(c) ** 0.5, c), cy + b * math.copysign(abs(s) ** 0.5, s), z))
    return pts


def band(lower, upper, outward):
    tris = []
    for i in range(segments):
        j = (i + 1) % segments
        a, b, c, d = lower[i], lower[j], upper[j], upper[i]
        if outward:
            tris += [(a, b, c), (a, c, d)]
        else:
            tris += [(a, c, b), (a, d, c)]
    return tris


def cap(loop, z, up):
    centre = (cx, cy, z)
    tris = []
    for i in range(segments):
        j = (i + 1) % segments
        tris.append((centre, loop[i], loop[j]) if up else (centre, loop[j], loop[i]))
    return tris


outer = [ring(height * k / rings, 0.0) for k in range(rings + 1)]
inner_z = [wall + (height - wall) * k / rings for k in range(rings + 1)]
inner = [ring(z, wall) for z in inner_z]
triangles = []
for k in range(rings):
    triangles += band(outer[k], outer[k + 1], True)
    triangles += band(inner[k], inner[k + 1], False)
triangles += band(inner[-1], outer[-1], False)  # the rim, facing up
triangles += cap(outer[0], 0.0, False)          # the bottom, facing down
triangles += cap(inner[0], wall, True)          # the floor's top, facing up into the tub


def normal(a, b, c):
    u = [b[k] - a[k] for k in range(3)]
    v = [c[k] - a[k] for k in range(3)]
    n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    m = math.sqrt(sum(x * x for x in n)) or 1.0
    return [x / m for x in n]


with open(out, "wb") as f:
    f.write(b"beadtwin hull mould".ljust(80, b" "))
    f.write(struct.pack("<I", len(triangles)))
    for t in triangles:
        f.write(struct.pack("<3f", *normal(*t)))
        for p in t:
            f.write(struct.pack("<3f", *p))
        f.write(b"\0\0")
