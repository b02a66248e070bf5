#!/usr/bin/env bash
# How a run grows with the part and the voxel size, so a user can predict a run before
# starting it: the LSAM hull-mould shell (bench/make_hull_mould.py, the wall kept at 41 mm) scaled to half,
# 0.71 and full size at 2 mm voxels, and the full size at 4 and 3 mm voxels, each run end to end once
# (`beadtwin run`, wall time and peak memory from /usr/bin/time, bench/common.sh's timed). Writes the table into docs/PERFORMANCE.md
# between the "scaling:begin" and "scaling:end" markers.
#
#   bash bench/scaling.sh [BUILD_DIR]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
build="${1:-$root/build}"
doc="$root/docs/PERFORMANCE.md"
bin="$build/tools/beadtwin"
[ -x "$bin" ] || { echo "build beadtwin first (cmake --build $build --target beadtwin)" >&2; exit 2; }
grep -q "scaling:begin" "$doc" && grep -q "scaling:end" "$doc" || { echo "$doc lacks the scaling markers" >&2; exit 2; }

: > "$work/rows"
run() {  # run SCALE VOXEL_MM
  local scale="$1" voxel="$2" dir="$work/s$1-v$2"
  write_hull_mould "$dir" "$(echo "1500 * $scale" | bc -l)" "$(echo "600 * $scale" | bc -l)" \
    "$(echo "500 * $scale" | bc -l)" 41 > /dev/null
  echo "scale $scale, voxels $voxel mm" >&2
  : > "$dir/run.txt"
  timed "$dir/run.txt" "$bin" run "$dir/hull-mould.yaml" --set "output.voxel_size=$voxel" -q -o "$dir/out"
  python3 - "$dir/out/report.json" "$(cat "$dir/run.txt")" "$scale" "$voxel" >> "$work/rows" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))["variants"][0]
m = r["metrics"]
seconds, mb = map(float, sys.argv[2].split())
st = r["stage_seconds"]
print(sys.argv[3], sys.argv[4], m["print_length_mm"] / 1000, m["deposit"]["voxels"] / 1e6, m["interfaces"]["count"],
      m["print_time_s"], seconds, mb, st.get("deposit", 0), st.get("compare", 0), st.get("thermal", 0),
      st.get("render", 0))
PY
}
run 0.5 2
run 0.71 2
run 1 2
run 1 3
run 1 4

python3 - "$work/rows" "$doc" "$(date -u +%Y-%m-%d)" "$(commit_id)" <<'PY'
import math, re, sys
rows = [list(map(float, l.split())) for l in open(sys.argv[1])]
out = ["<!-- scaling:begin: written by bench/scaling.sh; do not edit by hand -->", "",
       f"**Last run:** {sys.argv[3]}, commit {sys.argv[4]}, `bash bench/scaling.sh`: the hull shell scaled in "
       "length, width and height (wall 41 mm, two beads), end to end, once each.", "",
       "| scale | voxel | bead | voxels | interfaces | print | run | peak | s per m of bead | MB per M voxels "
       "| deposit | compare | thermal | render |",
       "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
for s, v, m, vox, itf, pt, t, mb, dep, cmp_, th, ren in rows:
    out.append(f"| {s:g} | {v:g} mm | {m:.0f} m | {vox:.1f} M | {itf:,.0f} | {pt / 3600:.1f} h | {t:.0f} s | "
               f"{mb:.0f} MB | {t / m:.3f} | {mb / vox:.0f} | {dep:.1f} s | {cmp_:.1f} s | {th:.1f} s | "
               f"{ren:.1f} s |")
def slope(a, b, x, y):  # log-log slope of column y against column x between rows a and b
    return math.log(rows[b][y] / rows[a][y]) / math.log(rows[b][x] / rows[a][x])
out += ["", f"At 2 mm voxels, run time grows as bead length to the power {slope(0, 2, 2, 6):.2f} and peak memory "
        f"as {slope(0, 2, 2, 7):.2f} (half size to full). At full size, run time grows as the voxel size to the power "
        f"{slope(4, 2, 1, 6):.2f} and peak memory as {slope(4, 2, 1, 7):.2f} (4 mm to 2 mm; the voxel count as "
        f"{slope(4, 2, 1, 3):.2f}). To predict a run: scale the nearest row by these powers.", "",
        "<!-- scaling:end -->", ""]
doc = open(sys.argv[2]).read()
doc = re.sub(r"<!-- scaling:begin.*?<!-- scaling:end -->\n", lambda _: "\n".join(out), doc, flags=re.S)
open(sys.argv[2], "w").write(doc)
print("\n".join(out))
PY
