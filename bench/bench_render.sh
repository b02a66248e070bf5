#!/usr/bin/env bash
# Render benchmark: the LSAM-scale hull-mould shell of bench/hull-mould.yaml (1.5 m x 0.6 m x
# 0.5 m, two beads thick, 2 mm voxels) and the built-in default scenario, each sliced and deposited as a run
# does, its surface extracted and its ray tracing structure built once, then FRAMES full-HD isometric
# pictures rendered from it with soft shadows and ambient occlusion (the defaults), and FRAMES with both off
# as the same run's reference. Prints, per scenario, the surface and structure times, the median time per
# frame and the rays traced per second; the pictures are written to OUT_DIR when given.
# Usage: bench/bench_render.sh [BUILD_DIR] [FRAMES] [OUT_DIR]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
build="${1:-$root/build}"
frames="${2:-5}"
out="${3:-}"
build_bench "$build" render_bench
write_hull_mould
for scenario in "$work/hull-mould.yaml" "$root/scenarios/data/default.yaml"; do
  name="$(basename "$scenario" .yaml)"
  echo "== $name"
  if [ -n "$out" ]; then
    mkdir -p "$out/$name"
    "$build/bench/render_bench" "$scenario" "$frames" 1920 1080 0 "$out/$name"
  else
    "$build/bench/render_bench" "$scenario" "$frames" 1920 1080
  fi
done
