#!/usr/bin/env bash
# A PrusaSlicer program of 100 MB and more: an 80 mm sphere sliced by Debian's prusa-slicer at
# 0.1 mm layers, 3 perimeters and 40 % gyroid fill (about 156 MB, 5.4 million lines, a 16-hour desktop
# print). `beadtwin read` against `wc -l` on it (medians of RUNS), then `beadtwin check` end to end once,
# stopped after LIMIT seconds: prints its time, peak memory and the print's own time, or how far it got.
# Usage: bench/prusa_program.sh [BUILD_DIR] [RUNS] [LIMIT_S]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
build="${1:-$root/build}"
runs="${2:-3}"
limit="${3:-900}"
command -v prusa-slicer >/dev/null || { echo "prusa-slicer is not installed (apt-get install prusa-slicer)"; exit 2; }
[ -x "$build/tools/beadtwin" ] || { echo "build beadtwin first (cmake --build $build --target beadtwin)"; exit 2; }

python3 "$root/bench/make_sphere_stl.py" "$work/sphere.stl" 40 96 > /dev/null
prusa-slicer --export-gcode --layer-height 0.1 --first-layer-height 0.2 --perimeters 3 --fill-density 40% \
  --fill-pattern gyroid --output "$work/prusa.gcode" "$work/sphere.stl" > /dev/null 2>&1
size=$(stat -c %s "$work/prusa.gcode")
lines=$(wc -l < "$work/prusa.gcode")
wall() { local t0 t1; t0=$(date +%s.%N); "$@" >/dev/null 2>&1; t1=$(date +%s.%N); echo "$t1 - $t0" | bc -l; }
wc_t=$(for _ in $(seq "$runs"); do wall wc -l "$work/prusa.gcode"; done | median)
bt=$(for _ in $(seq "$runs"); do wall "$build/tools/beadtwin" read "$work/prusa.gcode" --machine desktop-fff; done | median)
echo "prusa program: $((size / 1000000)) MB, $lines lines (80 mm sphere, 0.1 mm layers, 40 % gyroid)"
printf 'wc -l          (median of %s): %.3f s\n' "$runs" "$wc_t"
printf 'beadtwin read  (median of %s): %.3f s\n' "$runs" "$bt"
printf 'ratio beadtwin / wc -l: %.1f\n' "$(echo "$bt / $wc_t" | bc -l)"

rc=0
/usr/bin/time -f "%e %M" -o "$work/time.txt" timeout "$limit" "$build/tools/beadtwin" check "$work/prusa.gcode" \
  --machine desktop-fff -o "$work/check" > "$work/check.log" 2>&1 || rc=$?
read -r seconds kb < <(tail -1 "$work/time.txt")
peak_mb=$((kb / 1024))
sed -n 's/^\[program\] *//p' "$work/check.log" | sed 's/^/  stage /'
if [ "$rc" -le 1 ]; then
  print_s=$(python3 -c "import json; print(json.load(open('$work/check/report.json'))['variants'][0]['metrics']['print_time_s'])")
  printf 'beadtwin check: %.0f s, peak %s MB; its print: %.0f s\n' "$seconds" "$peak_mb" "$print_s"
else
  printf 'beadtwin check: stopped after %.0f s (limit %s s), peak %s MB\n' "$seconds" "$limit" "$peak_mb"
fi
grep -i "note\|voxel size" "$work/check.log" | head -3 || true
