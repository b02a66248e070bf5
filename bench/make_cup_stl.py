#!/usr/bin/env python3
"""Writes a binary STL of an open cup (a cylinder with a floor and no lid), the ordinary desktop print of the
fusion and performance benchmarks: make_cup_stl.py OUT [DIAMETER_MM HEIGHT_MM WALL_MM FLOOR_MM [SEGMENTS]]."""
import math
import struct
import sys

out = sys.argv[1]
diameter, height, wall, floor = (float(v) for v in (sys.argv[2:6] if len(sys.argv) > 5 else (60, 60, 2, 2)))
segments = int(sys.argv[6]) if len(sys.argv) > 6 else 128
r_out, r_in = diameter / 2.0, diameter / 2.0 - wall
centre = (r_out + 20.0, r_out + 20.0)


def ring(radius, z):
    return [(centre[0] + radius * math.cos(2 * math.pi * k / segments),
             centre[1] + radius * math.sin(2 * math.pi * k / segments), z) for k in range(segments)]


def quad(a, b, c, d):  # counter-clockwise seen from outside
    return [(a, b, c), (a, c, d)]


outer_bottom, outer_top = ring(r_out, 0.0), ring(r_out, height)
inner_floor, inner_top = ring(r_in, floor), ring(r_in, height)
bottom_centre, floor_centre = (centre[0], centre[1], 0.0), (centre[0], centre[1], floor)
triangles = []
for k in range(segments):
    n = (k + 1) % segments
    triangles += quad(outer_bottom[k], outer_bottom[n], outer_top[n], outer_top[k])  # outside, facing out
    triangles += quad(inner_floor[n], inner_floor[k], inner_top[k], inner_top[n])    # inside, facing in
    triangles += quad(outer_top[k], outer_top[n], inner_top[n], inner_top[k])        # rim, facing up
    triangles.append((bottom_centre, outer_bottom[n], outer_bottom[k]))              # base, facing down
    triangles.append((floor_centre, inner_floor[k], inner_floor[n]))                 # floor, facing up


def normal(a, b, c):
    u = [b[i] - a[i] for i in range(3)]
    v = [c[i] - a[i] for i in range(3)]
    n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    length = math.sqrt(sum(x * x for x in n)) or 1.0
    return tuple(x / length for x in n)


with open(out, "wb") as f:
    f.write(b"beadtwin cup".ljust(80, b" "))
    f.write(struct.pack("<I", len(triangles)))
    for t in triangles:
        f.write(struct.pack("<12fH", *normal(*t), *t[0], *t[1], *t[2], 0))
print(f"{out}: cup {diameter} mm across, {height} mm tall, wall {wall} mm, floor {floor} mm, {len(triangles)} triangles")
