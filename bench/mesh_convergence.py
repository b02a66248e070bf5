#!/usr/bin/env python3
"""Mesh convergence of the fusion verdicts: per-layer results of runs at several cell counts through and
across a bead, each against the finest. Usage: mesh_convergence.py DIR REF (DIR holds one run per
subdirectory tTaA, T cells through and A across; REF names the finest). Prints, per run, the largest
difference over the layers that land on a layer (the first lands on the table) of the layer means of the
substrate and surface temperatures and of the healing's layer mean and minimum, the middle layer's
layer-time window (the edges for 99 % of its landing area, then for the typical half) and the run's
too-cold fraction."""
import json
import os
import sys


def layer_value(layer, key, stat="mean"):
    value = layer.get(key)
    return value.get(stat) if isinstance(value, dict) else value


def largest_difference(layers, ref_layers, key, stat="mean"):
    diffs = [abs(layer_value(a, key, stat) - layer_value(b, key, stat))
             for a, b in zip(layers[1:], ref_layers[1:])
             if layer_value(a, key, stat) is not None and layer_value(b, key, stat) is not None]
    return max(diffs) if diffs else float("nan")


def edge(value):
    return "none" if value is None else f"{value:.1f}"


def main():
    root, ref_name = sys.argv[1], sys.argv[2]
    runs = {}
    for name in sorted(os.listdir(root)):
        path = os.path.join(root, name, "report.json")
        if os.path.exists(path):
            with open(path, encoding="utf-8") as f:
                runs[name] = json.load(f)["variants"][0]
    ref = runs[ref_name]["layers"]
    print(f"{'cells':>6} {'substrate K':>12} {'surface K':>10} {'healing':>8} {'min healing':>12}"
          f" {'window (99 %) s':>16} {'window (typical) s':>19} {'too cold':>9}")
    for name, variant in runs.items():
        layers = variant["layers"]
        window = layers[len(layers) // 2]["layer_time_window_s"]
        cold = variant["values"].get("interfaces.too_cold_fraction")
        print(f"{name:>6} {largest_difference(layers, ref, 'substrate_temp_c'):12.2f}"
              f" {largest_difference(layers, ref, 'surface_temp_c'):10.2f}"
              f" {largest_difference(layers, ref, 'healing_mean', None):8.3f}"
              f" {largest_difference(layers, ref, 'healing_min', None):12.3f}"
              f" {edge(window['min']) + '-' + edge(window['max']):>16}"
              f" {edge(window['typical_min']) + '-' + edge(window['typical_max']):>19}"
              f" {'-' if cold is None else f'{cold:.3f}':>9}")


if __name__ == "__main__":
    main()
