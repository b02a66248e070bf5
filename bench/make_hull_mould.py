#!/usr/bin/env python3
"""Writes a binary STL of an LSAM-scale hull-mould shell (the deposition benchmark's part):
make_hull_mould.py OUT [LENGTH_MM WIDTH_MM HEIGHT_MM WALL_MM] [--segments N] [--rings N] [--even-wall].

An open-top tub whose horizontal sections are rounded rectangles (superellipses, exponent 4) that flare
from 80 % of the top's size at the bottom to the full size at the top, like the female mould of a boat
hull; the floor is WALL_MM thick (two 0.83 in LSAM beads by default), and so is the wall where the sections
cross the axes: the inner section is the outer's with its semi-axes WALL_MM shorter, which leaves the wall
thicker at the rounded corners (up to 47 mm at the default size). With --even-wall the inner section is the
outer's offset in plan instead, and the wall is WALL_MM thick all round. Closed and outward-facing.

Each section is a polygon of SEGMENTS points (default 160: at most 0.14 mm from the true curve on the default
size; 96 gives 0.38 mm) and the wall is straight between RINGS + 1 sections spaced evenly in height (default
40; at 16 the wall stays within 0.35 mm of its curve above the floor, 2.8 mm in the floor's height, where
it flares fastest). A triangle takes 50 bytes: 4 SEGMENTS (RINGS + 1) triangles in all."""
import argparse
import math
import struct

parser = argparse.ArgumentParser(description="Writes a binary STL of an LSAM-scale hull-mould shell.")
parser.add_argument("out")
parser.add_argument("size", nargs="*", type=float, metavar="LENGTH_MM WIDTH_MM HEIGHT_MM WALL_MM",
                    help="outer length, width and height and the wall's thickness (default 1500 600 500 41)")
parser.add_argument("--segments", type=int, default=160, help="points round each section (default 160)")
parser.add_argument("--rings", type=int, default=40, help="straight bands of wall up the height (default 40)")
parser.add_argument("--even-wall", action="store_true",
                    help="make the inner face the outer's offset in plan, so the wall is WALL_MM thick all round "
                         "(by default the inner section is the outer's with semi-axes WALL_MM shorter: at the "
                         "default size 41 mm thick on the axes and up to 47 mm at the rounded corners)")
args = parser.parse_args()
if len(args.size) not in (0, 4):
    parser.error("give all four of LENGTH_MM WIDTH_MM HEIGHT_MM WALL_MM, or none")
if args.segments < 8 or args.rings < 1:
    parser.error("at least 8 segments and 1 ring")
out = args.out
length, width, height, wall = args.size or (1500, 600, 500, 41)
segments, rings = args.segments, args.rings
cx, cy = length / 2 + 50, width / 2 + 50


def semi_axes(z):
    t = (z / height) ** 0.7
    return (0.8 + 0.2 * t) * length / 2, (0.8 + 0.2 * t) * width / 2


def ring(z, inset):
    a, b = semi_axes(z)
    if not args.even_wall:
        a, b, inset = a - inset, b - inset, 0.0
    pts = []
    for i in range(segments):
        phi = 2 * math.pi * i / segments
        c, s = math.cos(phi), math.sin(phi)
        x, y = a * math.copysign(abs(c) ** 0.5, c), b * math.copysign(abs(s) ** 0.5, s)
        # The outward normal of |x/a|^4 + |y/b|^4 = 1 is along (x^3 / a^4, y^3 / b^4).
        nx, ny = x ** 3 / a ** 4, y ** 3 / b ** 4
        n = math.hypot(nx, ny)
        pts.append((cx + x - inset * nx / n, cy + y - inset * ny / n, z))
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
