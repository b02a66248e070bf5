#!/usr/bin/env bash
# Slicing benchmark: the same STL sliced by beadtwin and by PrusaSlicer (Debian's prusa-slicer) at
# comparable settings — 5 mm layers, 21 mm extrusion width, 2 perimeters, solid rectilinear fill — in one run
# on one machine. Prints the median wall time of each over RUNS runs and their ratio.
# Usage: bench/slice_vs_prusa.sh [BUILD_DIR] [RUNS]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
build="${1:-$root/build}"
runs="${2:-5}"

command -v prusa-slicer >/dev/null || { echo "prusa-slicer is not installed (apt-get install prusa-slicer)"; exit 2; }
[ -x "$build/tools/beadtwin" ] || { echo "build beadtwin first (cmake --build $build --target beadtwin)"; exit 2; }

python3 "$root/bench/make_sphere_stl.py" "$work/sphere.stl" 200 192
cat > "$work/sphere.yaml" <<YAML
name: sphere-slice-bench
units: {length: mm}
machine: lsam-ph15
material: cf-abs-20
part: {mesh: sphere.stl}
sections:
  - {name: all, z: part, layer_height: 5, bead_width: 21, boundary: {passes: 2}, fill: {angle: 45 deg, angle_step: 90 deg}}
YAML

wall() { local t0 t1; t0=$(date +%s.%N); "$@" >/dev/null 2>&1; t1=$(date +%s.%N); echo "$t1 - $t0" | bc -l; }

bt=$(for _ in $(seq "$runs"); do wall "$build/tools/beadtwin" slice "$work/sphere.yaml" -o "$work/bt.nc"; done | median)
ps=$(for _ in $(seq "$runs"); do
  wall prusa-slicer --export-gcode --nozzle-diameter 21 --layer-height 5 --first-layer-height 5 --perimeters 2 \
    --fill-density 100% --fill-pattern rectilinear --top-solid-layers 0 --bottom-solid-layers 0 \
    --extrusion-width 21 --bed-shape 0x0,1000x0,1000x1000,0x1000 --max-print-height 1000 \
    --output "$work/ps.gcode" "$work/sphere.stl"
done | median)
bt_layers=$(grep -c "(LAYER " "$work/bt.nc")
ps_layers=$(grep -c ";LAYER_CHANGE" "$work/ps.gcode")
printf "part: 400 mm UV sphere, 36480 triangles; layers: beadtwin %s, PrusaSlicer %s\n" "$bt_layers" "$ps_layers"
printf "beadtwin slice (median of %s): %.3f s\n" "$runs" "$bt"
printf "prusa-slicer   (median of %s): %.3f s\n" "$runs" "$ps"
printf "ratio beadtwin / prusa-slicer: %.2f\n" "$(echo "$bt / $ps" | bc -l)"
