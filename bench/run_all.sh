#!/usr/bin/env bash
# The benchmark suite: every workload, each against its reference measured in the same run on the
# same machine, written into docs/PERFORMANCE.md between the "bench:begin" and "bench:end" markers (the
# sections below them keep the history and the analysis). One command:
#
#   bash bench/run_all.sh [BUILD_DIR] [RUNS]      RUNS (default 3) of each short workload; the LSAM-scale
#                                                 mould and the PrusaSlicer program's check run once
#                                                 (about 40 min in all on two cores)
#
# Workloads and their references:
#   default scenario end to end   `beadtwin run` with no scenario            the print time (real-time factor)
#   LSAM mould end to end         `beadtwin run` on bench/hull-mould.yaml    the print time; stage by stage
#   slicing                       `beadtwin slice` on a 400 mm sphere STL    prusa-slicer on the same STL
#   reading a program             `beadtwin read` on a 100 MB program        wc -l on the same file
#   deposition                    the mould's deposit                        OpenVDB mesh-to-volume of the
#                                                                            same beads as swept tubes
#   rendering                     1920x1080 of the mould                     the 2 s goal (no peer here)
#   a PrusaSlicer program         `beadtwin check` on a 155 MB program       the print time; `beadtwin read`
#                                 (bench/prusa_program.sh, an hour at most)   against wc -l on it
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
build="${1:-$root/build}"
runs="${2:-3}"
doc="$root/docs/PERFORMANCE.md"
bin="$build/tools/beadtwin"
[ -x "$bin" ] || { echo "build beadtwin first (cmake --build $build --target beadtwin)" >&2; exit 2; }
grep -q "bench:begin" "$doc" && grep -q "bench:end" "$doc" || { echo "$doc lacks the bench markers" >&2; exit 2; }
build_bench "$build" deposit_bench
build_bench "$build" render_bench

log="$work/log.txt"
say() { echo "$*" | tee -a "$log" >&2; }
# json FILE EXPR: a value from a report.json (python3's json; no other tool needed).
json() { python3 -c "import json,sys; r=json.load(open(sys.argv[1])); print($2)" "$1"; }
col() { awk -v c="$2" '{print $c}' "$1" | median; }
ratio() { echo "$1 / $2" | bc -l | xargs printf "%.${3:-2}f"; }

# 1. The default scenario end to end.
say "default scenario, $runs runs"
: > "$work/default.runs"
for _ in $(seq "$runs"); do timed "$work/default.runs" "$bin" run -q -o "$work/default"; done
def_s=$(col "$work/default.runs" 1)
def_mb=$(col "$work/default.runs" 2)
def_print=$(json "$work/default/report.json" "r['variants'][0]['metrics']['print_time_s']")

# 2. The LSAM-scale mould end to end, once, with its stages.
say "LSAM mould end to end"
write_hull_mould
: > "$work/mould.runs"
timed "$work/mould.runs" "$bin" run "$work/hull-mould.yaml" -q -o "$work/mould"
mould_s=$(col "$work/mould.runs" 1)
mould_mb=$(col "$work/mould.runs" 2)
mould_print=$(json "$work/mould/report.json" "r['variants'][0]['metrics']['print_time_s']")
stages=$(json "$work/mould/report.json" \
  "' · '.join(f'{k} {v:.1f} s' for k, v in sorted(r['variants'][0]['stage_seconds'].items(), key=lambda kv: -kv[1]))")

# 3. Slicing against PrusaSlicer, 4. reading against wc -l, 5. deposition against mesh-to-volume,
# 6. rendering: each workload's own script or program, its summary lines kept.
say "slicing against prusa-slicer"
bash "$root/bench/slice_vs_prusa.sh" "$build" "$runs" > "$work/slice.txt"
say "reading a 100 MB program against wc -l"
bash "$root/bench/read_vs_wc.sh" "$build" "$runs" 100 > "$work/read.txt"
say "deposition against mesh-to-volume"
bash "$root/bench/bench_deposit.sh" "$build" 1 > "$work/deposit.txt"
say "rendering"
"$build/bench/render_bench" "$work/hull-mould.yaml" 5 1920 1080 > "$work/render.txt"
say "a PrusaSlicer program through check"
bash "$root/bench/prusa_program.sh" "$build" "$runs" 3600 > "$work/prusa.txt"

grab() { grep -m1 "$2" "$1" | sed 's/.*: *//'; }
slice_bt=$(grab "$work/slice.txt" "^beadtwin slice" | awk '{print $1}')
slice_ps=$(grab "$work/slice.txt" "^prusa-slicer" | awk '{print $1}')
read_wc=$(grab "$work/read.txt" "^wc -l" | awk '{print $1}')
read_bt=$(grab "$work/read.txt" "^beadtwin read" | awk '{print $1}')
dep_line=$(grep -m1 "^beadtwin deposit" "$work/deposit.txt")
dep_s=$(echo "$dep_line" | sed 's/.*: \([0-9.]*\) s.*/\1/')
mesh_s=$(grep -m1 "^mesh-to-volume" "$work/deposit.txt" | sed 's/.*: \([0-9.]*\) s.*/\1/')
render_s=$(grep -m1 "^full" "$work/render.txt" | sed 's/.*frame \([0-9.]*\) s.*/\1/')
prusa_size=$(grep -m1 "^prusa program" "$work/prusa.txt" | sed 's/prusa program: \([0-9]*\) MB, \([0-9]*\) lines.*/\1 MB, \2 lines/')
prusa_wc=$(grab "$work/prusa.txt" "^wc -l" | awk '{print $1}')
prusa_read=$(grab "$work/prusa.txt" "^beadtwin read" | awk '{print $1}')
if grep -q "^beadtwin check: stopped" "$work/prusa.txt"; then
  prusa_check="did not finish in $(grep -m1 "^beadtwin check" "$work/prusa.txt" | sed 's/.*stopped after \([0-9]*\) s.*/\1/') s"
  prusa_ratio="-"
else
  read -r prusa_s prusa_mb prusa_print < <(grep -m1 "^beadtwin check" "$work/prusa.txt" |
    sed 's/beadtwin check: \([0-9.]*\) s, peak \([0-9]*\) MB; its print: \([0-9.]*\) s/\1 \2 \3/')
  prusa_check="$prusa_s s, peak $prusa_mb MB"
  prusa_ratio="$(ratio "$prusa_print" "$prusa_s" 0) x faster than printing"
  prusa_print="its print: $prusa_print s"
fi

machine="$(nproc) cores ($(grep -m1 "model name" /proc/cpuinfo | sed 's/.*: //')), $(free -g | awk '/Mem:/ {print $2}') GiB, $(. /etc/os-release && echo "$PRETTY_NAME")"
commit="$(commit_id)"
mark() { if [ "$(echo "$1" | bc -l)" = 1 ]; then echo "met"; else echo "**not met**"; fi; }

{
  echo "<!-- bench:begin: written by bench/run_all.sh; do not edit by hand -->"
  echo
  echo "**Last suite run:** $(date -u +%Y-%m-%d), commit $commit, $machine. Command:"
  echo "\`bash bench/run_all.sh $( [ "$build" = "$root/build" ] || echo "$build ")$runs\` (medians of $runs runs; the mould end to end once)."
  echo
  echo "| workload | beadtwin | reference (same run) | ratio | goal | |"
  echo "|---|---|---|---|---|---|"
  printf '| default scenario, end to end | %.1f s, peak %s MB | its print: %.0f s | %s x faster than printing | under 10 s | %s |\n' \
    "$def_s" "$def_mb" "$def_print" "$(ratio "$def_print" "$def_s" 0)" "$(mark "$def_s < 10")"
  printf '| LSAM mould (1.5 m hull shell, 2 mm voxels), end to end | %.0f s, peak %s MB | its print: %.0f s | %s x faster than printing | 1000 x; peak under 4096 MB | %s; %s |\n' \
    "$mould_s" "$mould_mb" "$mould_print" "$(ratio "$mould_print" "$mould_s" 0)" \
    "$(mark "$mould_print / $mould_s >= 1000")" "$(mark "$mould_mb < 4096")"
  printf '| slicing a 400 mm sphere (36,480 triangles) | %s s | prusa-slicer: %s s | %s | at most 1 | %s |\n' \
    "$slice_bt" "$slice_ps" "$(ratio "$slice_bt" "$slice_ps")" "$(mark "$slice_bt <= $slice_ps")"
  printf '| reading a 100 MB program (3.3 M lines) | %s s | wc -l: %s s | %s | at most 5 | %s |\n' \
    "$read_bt" "$read_wc" "$(ratio "$read_bt" "$read_wc" 0)" "$(mark "$read_bt <= 5 * $read_wc")"
  printf '| depositing the mould | %s s | mesh-to-volume of the same beads: %s s | %s | | |\n' \
    "$dep_s" "$mesh_s" "$(ratio "$dep_s" "$mesh_s")"
  printf '| rendering the mould, 1920 x 1080 | %s s a frame | | | under 2 s | %s |\n' \
    "$render_s" "$(mark "$render_s < 2")"
  printf '| a PrusaSlicer program (%s, a 16-hour print), checked end to end | %s | %s | %s | | |\n' \
    "$prusa_size" "$prusa_check" "${prusa_print:-its print}" "$prusa_ratio"
  printf '| reading that program | %s s | wc -l: %s s | %s | at most 5 | %s |\n' \
    "$prusa_read" "$prusa_wc" "$(ratio "$prusa_read" "$prusa_wc" 0)" "$(mark "$prusa_read <= 5 * $prusa_wc")"
  echo
  echo "Mould stages: $stages."
  echo
  echo "<details><summary>The suite's own output</summary>"
  echo
  echo '```'
  for f in slice read deposit render prusa; do cat "$work/$f.txt"; done
  echo '```'
  echo
  echo "</details>"
  echo
  echo "<!-- bench:end -->"
} > "$work/section.md"

python3 - "$doc" "$work/section.md" <<'PY'
import re, sys
doc, section = sys.argv[1], open(sys.argv[2]).read()
text = open(doc).read()
text = re.sub(r"<!-- bench:begin.*?<!-- bench:end -->\n", lambda m: section, text, flags=re.S)
open(doc, "w").write(text)
PY
cat "$work/section.md"
