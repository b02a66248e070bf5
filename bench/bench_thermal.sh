#!/usr/bin/env bash
# Thermal benchmark: the LSAM-scale hull-mould shell of bench/hull-mould.yaml (the deposition
# benchmark's part: 1.5 m x 0.6 m x 0.5 m, two beads thick, 2 mm voxels) and the built-in default scenario,
# each sliced and deposited as a run does, then the thermal mesh built and the heat transfer solved. The
# reference is the print itself: the real-time factor is the simulated time (the print and its cooldown)
# over the solve's wall time, and the print alone over it. Each scenario runs RUNS times in a process of its
# own; prints the median solve time, real-time factors and the peak memory of the whole process.
# Usage: bench/bench_thermal.sh [BUILD_DIR] [RUNS]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
build="${1:-$root/build}"
runs="${2:-3}"
build_bench "$build" thermal_bench
write_hull_mould
for scenario in "$work/hull-mould.yaml" "$root/scenarios/data/default.yaml"; do
  : > "$work/runs"
  for _ in $(seq "$runs"); do
    /usr/bin/time -f "%M" -o "$work/time.txt" "$build/bench/thermal_bench" "$scenario" > "$work/out.txt"
    # heat <seconds> s ...; simulated <S> s (print <P> s)
    heat=$(awk '/^heat / {print $2}' "$work/out.txt")
    simulated=$(awk '/^simulated / {print $2}' "$work/out.txt")
    print=$(awk '/^simulated / {gsub(/[()]/, ""); print $5}' "$work/out.txt")
    echo "$heat $simulated $print $(cat "$work/time.txt")" >> "$work/runs"
  done
  cat "$work/out.txt"
  heat_s=$(awk '{print $1}' "$work/runs" | median)
  simulated_s=$(awk '{print $2}' "$work/runs" | median)
  print_s=$(awk '{print $3}' "$work/runs" | median)
  peak_mb=$(awk '{print $4 / 1024}' "$work/runs" | median)
  printf '%s (median of %s): solve %.1f s, real-time factor %.0f (print only %.0f), peak %.0f MB\n' \
    "$(basename "$scenario")" "$runs" "$heat_s" "$(echo "$simulated_s / $heat_s" | bc -l)" \
    "$(echo "$print_s / $heat_s" | bc -l)" "$peak_mb"
done
