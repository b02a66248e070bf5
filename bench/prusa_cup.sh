#!/usr/bin/env bash
# An ordinary desktop PLA print, sliced from a mesh by Debian's prusa-slicer: an open cup (bench/make_cup_stl.py;
# by default 40 mm across, 30 mm tall, 1.6 mm wall, 1.2 mm floor, a 45-minute print) at 0.2 mm layers, two
# perimeters, 15 % fill, 215 C nozzle, 60 C bed, PLA cooling (fan) on; then `beadtwin check` of it with the
# desktop-fff machine and the pla material. Prints the check's time and peak memory against the print's own
# time, and its fusion verdicts (docs/validation.md, the desktop print). Such prints come off printers sound.
# Usage: bench/prusa_cup.sh [BUILD_DIR] [DIAMETER_MM HEIGHT_MM WALL_MM FLOOR_MM] [-- beadtwin check options]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
build="${1:-$root/build}"
shift || true
size=(40 30 1.6 1.2)
if [ $# -ge 4 ] && [ "$1" != "--" ]; then size=("$1" "$2" "$3" "$4"); shift 4; fi
[ "${1:-}" = "--" ] && shift
command -v prusa-slicer >/dev/null || { echo "prusa-slicer is not installed (apt-get install prusa-slicer)"; exit 2; }
[ -x "$build/tools/beadtwin" ] || { echo "build beadtwin first (cmake --build $build --target beadtwin)"; exit 2; }

python3 "$root/bench/make_cup_stl.py" "$work/cup.stl" "${size[@]}"
prusa-slicer --export-gcode --layer-height 0.2 --first-layer-height 0.2 --perimeters 2 --fill-density 15% \
  --temperature 215 --first-layer-temperature 215 --bed-temperature 60 --first-layer-bed-temperature 60 \
  --filament-type PLA --cooling --output "$work/cup.gcode" "$work/cup.stl" > /dev/null 2>&1
grep -m1 "estimated printing time (normal mode)" "$work/cup.gcode" | sed 's/^; /prusa-slicer: /'
rc=0
/usr/bin/time -f "%e %M" -o "$work/time.txt" "$build/tools/beadtwin" check "$work/cup.gcode" --machine desktop-fff \
  --material pla -o "$work/check" -q "$@" > "$work/check.log" 2>&1 || rc=$?
[ "$rc" -le 1 ] || { cat "$work/check.log" >&2; exit 1; }
read -r seconds kb < <(tail -1 "$work/time.txt")
python3 - "$work/check/report.json" "$seconds" "$((kb / 1024))" <<'PY'
import json, sys
variant = json.load(open(sys.argv[1]))["variants"][0]
values = variant["values"]
print(f"beadtwin check: {float(sys.argv[2]):.0f} s, peak {sys.argv[3]} MB; its print: {values['print_time_s']:.0f} s")
print("interfaces: {:.0f}, too cold {:.3f}, too hot {:.3f}, mean healing {:.3f}, least {:.3f}".format(
    values["interfaces.count"], values["interfaces.too_cold_fraction"], values["interfaces.too_hot_fraction"],
    values["interfaces.mean_healing"], values["interfaces.min_healing"]))
layers = [l for l in variant["layers"] if l.get("substrate_temp_c") and l["substrate_temp_c"].get("mean") is not None]
mid = layers[len(layers) // 2]
print(f"middle layer {mid['index']}: substrate {mid['substrate_temp_c']['mean']:.1f} C, surface "
      f"{mid['surface_temp_c']['mean']:.1f} C, healing mean {mid['healing_mean']:.3f}")
PY
