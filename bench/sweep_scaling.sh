#!/usr/bin/env bash
# How a parameter sweep scales (docs/scaling.md): the same sweep of the built-in default scenario
# (the LSAM open box, its wall speed at six values: six variants) run plainly with one and two variants at
# once, and under mpirun with one rank (which runs the sweep plainly), and two and three ranks (rank 0
# hands out, the others run: one and two workers), each from an empty output folder, timed end to end. The
# reference is the first, one variant at a time on this machine. Prints a Markdown table for
# docs/scaling.md. Needs beadtwin built with MPI for the mpirun rows.
#
#   bash bench/sweep_scaling.sh [BUILD_DIR]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
build="${1:-$root/build}"
bin="$build/tools/beadtwin"
[ -x "$bin" ] || { echo "build beadtwin first (cmake --build $build --target beadtwin)" >&2; exit 2; }
sweep=(sweep --set "sections.walls.speed=1in/s,1.25in/s,1.5in/s,1.75in/s,2in/s,2.5in/s"
       --pareto print_time_s,interfaces.too_hot_fraction -q)
mpirun=(mpirun --allow-run-as-root --oversubscribe)

# row LABEL CMD...: runs the sweep into a fresh folder; prints "LABEL seconds peak_MB variants".
row() {
  local label="$1" dir="$work/$2"
  shift 2
  echo "$label" >&2
  : > "$work/t.txt"
  /usr/bin/time -f "%e %M" -o "$work/t.txt" "$@" -o "$dir" > /dev/null 2> "$work/err.txt" || true
  python3 - "$dir/sweep.json" "$(tail -1 "$work/t.txt")" "$label" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
seconds, kb = map(float, sys.argv[2].split())
per = [v["wall_time_s"] for v in s["variants"]]
print(f'{sys.argv[3]}\t{seconds:.1f}\t{len(per)}\t{sum(per) / len(per):.1f}\t{s["engine"]}')
PY
}

{
  row "plain, 1 at a time" plain1 "$bin" "${sweep[@]}"
  row "plain, --jobs 2" plain2 "$bin" "${sweep[@]}" --jobs 2
  if command -v mpirun > /dev/null; then
    row "mpirun -n 1" mpi1 "${mpirun[@]}" -n 1 "$bin" "${sweep[@]}"
    row "mpirun -n 2" mpi2 "${mpirun[@]}" -n 2 "$bin" "${sweep[@]}"
    row "mpirun -n 3" mpi3 "${mpirun[@]}" -n 3 "$bin" "${sweep[@]}"
  fi
} > "$work/rows.tsv"

echo "**$(date -u +%Y-%m-%d), commit $(commit_id), $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2 / 1048576}' /proc/meminfo).** \`bash bench/sweep_scaling.sh\`: six variants of the built-in scenario."
echo
echo "| how | sweep | variants | mean variant | speed-up | engine |"
echo "|---|---|---|---|---|---|"
awk -F'\t' 'NR == 1 {ref = $2} {printf "| %s | %.1f s | %d | %.1f s | %.2f | %s |\n", $1, $2, $3, $4, ref / $2, $5}' "$work/rows.tsv"
