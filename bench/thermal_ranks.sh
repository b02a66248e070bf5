#!/usr/bin/env bash
# One part's thermal solve shared among MPI ranks (docs/scaling.md): the built-in default scenario and the
# LSAM-scale hull mould of bench/hull-mould.yaml (or the scenario given) each sliced and deposited as a run
# does, then its heat transfer solved by thermal_ranks_bench on one
# rank with one thread (the reference), one rank with two threads, and two ranks of one thread each, each
# run RUNS times (the median solve time). Prints a Markdown table with each row's speed-up over the
# reference and how far its answer is from the reference's (bench/compare_thermal.py). Needs MPI.
#
#   bash bench/thermal_ranks.sh [BUILD_DIR] [RUNS] [SCENARIO]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
build="${1:-$root/build}"
runs="${2:-3}"
scenarios=("${3:-}")
command -v mpirun > /dev/null || { echo "needs mpirun (tools/setup.sh installs Open MPI)" >&2; exit 2; }
build_bench "$build" thermal_ranks_bench
bin="$build/bench/thermal_ranks_bench"
if [ -z "${scenarios[0]}" ]; then
  write_hull_mould
  scenarios=("$root/scenarios/data/default.yaml" "$work/hull-mould.yaml")
fi
mpirun=(mpirun --allow-run-as-root --oversubscribe --bind-to none)

# row LABEL RANKS THREADS: prints "LABEL<TAB>median solve seconds", leaves the last run's dump in LABEL.dump.
row() {
  local label="$1" ranks="$2" threads="$3"
  : > "$work/runs"
  for _ in $(seq "$runs"); do
    THERMAL_BENCH_THREADS="$threads" THERMAL_BENCH_DUMP="$work/$ranks-$threads.dump" \
      "${mpirun[@]}" -n "$ranks" -x THERMAL_BENCH_THREADS -x THERMAL_BENCH_DUMP "$bin" "$scenario" \
      > "$work/out.txt" < /dev/null
    awk '/^heat / {print $2}' "$work/out.txt" >> "$work/runs"
  done
  printf '%s\t%s\n' "$label" "$(median < "$work/runs")"
}

for scenario in "${scenarios[@]}"; do
  echo
  echo "$(basename "$scenario"):"
  echo
  echo "| how | thermal solve | speed-up | answer against the reference (max) |"
  echo "|---|---|---|---|"
  reference=""
  while read -r ranks threads label; do
    line=$(row "$label" "$ranks" "$threads")
    seconds=$(cut -f2 <<< "$line")
    [ -n "$reference" ] || reference="$seconds"
    differs="(reference)"
    if [ "$ranks-$threads" != "1-1" ]; then
      differs=$(python3 "$root/bench/compare_thermal.py" "$work/1-1.dump" "$work/$ranks-$threads.dump" |
                awk -F'max ' '/^substrate/ {split($2, a, " "); s = a[1]} /^healing/ {split($2, a, " "); h = a[1]}
                              END {printf "substrate %s K, healing %s", s, h}')
    fi
    printf '| %s | %.2f s | %.2f | %s |\n' "$label" "$seconds" "$(echo "$reference / $seconds" | bc -l)" "$differs"
  done <<'ROWS'
1 1 1 rank, 1 thread
1 2 1 rank, 2 threads
2 1 2 ranks, 1 thread each
ROWS
done
