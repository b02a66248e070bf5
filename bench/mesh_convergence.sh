#!/usr/bin/env bash
# Mesh convergence of the fusion verdicts (docs/validation.md, mesh convergence): the shipped Compton wall,
# its first 40 layers at 1.016 mm voxels (four voxel rows per layer, about twenty across the bead), run with
# 1, 2 and 4 thermal cells through each bead and 3, 5 and 9 across it; each run's per-layer substrate and
# surface temperatures, healing and middle layer's layer-time window against the finest (4 x 9, every slice
# kept to the end: thermal.lump false), by bench/mesh_convergence.py. The other runs lump as a run does by
# default: a bead's slices become one cell once two beads lie over it. With --default, also the built-in
# default scenario's baseline at 1, 2 and 4 through and 3 and 5 across, against 2 x 5 with every slice kept
# (about 5 minutes more).
# Usage: bench/mesh_convergence.sh [BUILD_DIR] [--default]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
build="${1:-$root/build}"
beadtwin="$build/tools/beadtwin"
run() {  # run DIR THROUGH ACROSS SCENARIO [--set ...]
  local dir="$1" through="$2" across="$3" scenario="$4"
  shift 4
  local rc=0
  "$beadtwin" run "$scenario" -o "$dir/t${through}a${across}" --variant baseline -q \
    --set "thermal.cells_through=$through" --set "thermal.cells_across=$across" "$@" > /dev/null || rc=$?
  [ "$rc" -le 1 ] || return 1  # 1: the scenario's own gates failed, a finished run
}
echo "Compton wall, 40 layers, 1.016 mm voxels ($(commit_id)):"
for through in 1 2 4; do
  for across in 3 5 9; do
    keep=()
    [ "$through$across" = 49 ] && keep=(--set thermal.lump=false)
    run "$work/wall" "$through" "$across" "$root/scenarios/data/compton-wall.yaml" \
      --set output.voxel_size=1.016mm --set sections.wall.layers=40 "${keep[@]}"
  done
done
python3 "$root/bench/mesh_convergence.py" "$work/wall" t4a9
if [ "${2:-}" = "--default" ]; then
  echo "Default scenario, baseline ($(commit_id)):"
  for through in 1 2 4; do
    for across in 3 5; do
      [ "$through$across" = 45 ] && continue
      keep=()
      [ "$through$across" = 25 ] && keep=(--set thermal.lump=false)
      run "$work/default" "$through" "$across" "$root/scenarios/data/default.yaml" "${keep[@]}"
    done
  done
  python3 "$root/bench/mesh_convergence.py" "$work/default" t2a5
fi
