#!/usr/bin/env bash
# Deposition benchmark: the LSAM-scale hull-mould shell of bench/hull-mould.yaml (1.5 m x 0.6 m x
# 0.5 m, two beads thick, 2 mm voxels) deposited by beadtwin, and in the same run the route a user would
# take instead: the beads as a swept-tube surface mesh voxelised by OpenVDB's mesh-to-volume. Each route runs
# RUNS times in a process of its own; prints the median time, the peak memory and the ratio.
# Usage: bench/bench_deposit.sh [BUILD_DIR] [RUNS]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
build="${1:-$root/build}"
runs="${2:-3}"
build_bench "$build" deposit_bench
write_hull_mould
route() {  # route -> lines "seconds peak_kB" and the program's own line in $work/$1.txt
  for _ in $(seq "$runs"); do
    /usr/bin/time -f "%e %M" -o "$work/time.txt" "$build/bench/deposit_bench" "$work/hull-mould.yaml" "$1" > "$work/$1.txt"
    echo "$(awk '{print $2}' "$work/$1.txt") $(awk '{print $2}' "$work/time.txt")"
  done
}
route deposit > "$work/deposit.runs"
route mesh > "$work/mesh.runs"
dep_s=$(awk '{print $1}' "$work/deposit.runs" | median)
mesh_s=$(awk '{print $1}' "$work/mesh.runs" | median)
dep_mb=$(awk '{print $2 / 1024}' "$work/deposit.runs" | median)
mesh_mb=$(awk '{print $2 / 1024}' "$work/mesh.runs" | median)
length_m=$(awk '{print $4}' "$work/deposit.txt")
cat "$work/deposit.txt" "$work/mesh.txt"
printf 'beadtwin deposit  (median of %s): %.1f s, peak %.0f MB, %.0f m of bead per second\n' "$runs" "$dep_s" "$dep_mb" \
  "$(echo "$length_m / $dep_s" | bc -l)"
printf 'mesh-to-volume    (median of %s): %.1f s, peak %.0f MB\n' "$runs" "$mesh_s" "$mesh_mb"
printf 'ratio deposit / mesh-to-volume: time %.2f, memory %.2f\n' "$(echo "$dep_s / $mesh_s" | bc -l)" \
  "$(echo "$dep_mb / $mesh_mb" | bc -l)"
echo "file sizes (bead-by-bead model against the as-printed skin at simplification tolerances 0 to 1 mm):"
"$build/bench/deposit_bench" "$work/hull-mould.yaml" skin "$work"
