#!/usr/bin/env python3
"""Compares two thermal_bench dumps (THERMAL_BENCH_DUMP): the interfaces' substrate temperatures, healing
integrals and verdicts, the cells' final temperatures and the layers' histories.
Usage: bench/compare_thermal.py REFERENCE OTHER"""
import math
import sys


def load(path):
    out = {"i": [], "c": [], "l": []}
    with open(path) as f:
        for line in f:
            kind, *values = line.split()
            out[kind].append([float(v) for v in values])
    return out


def stats(diffs):
    diffs = sorted(abs(d) for d in diffs if not math.isnan(d))
    if not diffs:
        return "none"
    p = lambda q: diffs[min(len(diffs) - 1, int(q * len(diffs)))]
    return f"median {p(0.5):.3g}, p99 {p(0.99):.3g}, max {diffs[-1]:.3g} (n {len(diffs)})"


a, b = load(sys.argv[1]), load(sys.argv[2])
assert len(a["i"]) == len(b["i"]) and len(a["c"]) == len(b["c"]), "different meshes"
print("substrate temperature, K:", stats([x[0] - y[0] for x, y in zip(a["i"], b["i"])]))
print("healing D_h (min 1, integral^1/4):",
      stats([min(1, x[1] ** 0.25) - min(1, y[1] ** 0.25) for x, y in zip(a["i"], b["i"])]))
changed = sum(1 for x, y in zip(a["i"], b["i"]) if x[2] != y[2])
print(f"verdicts changed: {changed} of {len(a['i'])}")
print("final cell temperature, K:", stats([x[0] - y[0] for x, y in zip(a["c"], b["c"])]))
print("layer history, K:", stats([x[0] - y[0] for x, y in zip(a["l"], b["l"])]))
