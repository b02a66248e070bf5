#!/usr/bin/env bash
# Reading benchmark: a G-code program of at least 100 MB read by `beadtwin read` (lexer, reader
# and motion timing, one thread) and counted by `wc -l`, on the same file in the same run. Prints the
# median wall time of each over RUNS runs and their ratio, and three floors, measured in the same run: the
# binary starting (`beadtwin --version`), writing one Move per line into the Toolpath with nothing parsed
# (bench/toolpath_floor.cpp), and every number of the program lexed on two threads with nothing kept
# (bench/lex_floor.cpp); both compiled here.
# Usage: bench/read_vs_wc.sh [BUILD_DIR] [RUNS] [MEGABYTES]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
build="${1:-$root/build}"
runs="${2:-3}"
megabytes="${3:-100}"
[ -x "$build/tools/beadtwin" ] || { echo "build beadtwin first (cmake --build $build --target beadtwin)"; exit 2; }

python3 "$root/bench/make_gcode.py" "$work/big.gcode" "$megabytes"
size=$(stat -c %s "$work/big.gcode")
wall() { local t0 t1; t0=$(date +%s.%N); "$@" >/dev/null 2>&1; t1=$(date +%s.%N); echo "$t1 - $t0" | bc -l; }

wc_t=$(for _ in $(seq "$runs"); do wall wc -l "$work/big.gcode"; done | median)
lines=$(wc -l < "$work/big.gcode")
g++ -O2 -std=c++20 -I"$root" -I/usr/include/eigen3 "$root/bench/toolpath_floor.cpp" \
  "$root/core/memory.cpp" -o "$work/toolpath_floor"
floor=$(for _ in $(seq "$runs"); do "$work/toolpath_floor" "$lines"; done | median)
g++ -O2 -std=c++20 -pthread "$root/bench/lex_floor.cpp" -o "$work/lex_floor"
lex=$(for _ in $(seq "$runs"); do wall "$work/lex_floor" "$work/big.gcode" 2; done | median)
start=$(for _ in $(seq "$runs"); do wall "$build/tools/beadtwin" --version; done | median)
bt=$(for _ in $(seq "$runs"); do wall "$build/tools/beadtwin" read "$work/big.gcode" --machine desktop-fff; done | median)
# The same reads' CPU time, user and system apart: the user time is the reader's own work; the system time is
# mostly fresh pages for the moves, which on a virtual machine costs from a tenth of the user time (pages
# the kernel has at hand) to twice it (pages the host must supply), whatever the reader does.
cpu() { /usr/bin/time -f "%U %S" -o "$work/cpu.txt" "$@" > /dev/null 2>&1; cat "$work/cpu.txt"; }
for _ in $(seq "$runs"); do cpu "$build/tools/beadtwin" read "$work/big.gcode" --machine desktop-fff; done > "$work/read_cpu.txt"
bt_user=$(awk '{print $1}' "$work/read_cpu.txt" | median)
bt_sys=$(awk '{print $2}' "$work/read_cpu.txt" | median)
"$build/tools/beadtwin" read "$work/big.gcode" --machine desktop-fff 2>/dev/null | head -4
echo "program: $((size / 1000000)) MB, $lines lines"
printf 'wc -l          (median of %s): %.3f s\n' "$runs" "$wc_t"
printf 'beadtwin read  (median of %s): %.3f s\n' "$runs" "$bt"
printf 'its CPU time   (median of %s): user %.2f s, system %.2f s\n' "$runs" "$bt_user" "$bt_sys"
printf 'starting the binary (beadtwin --version): %.3f s, ratio %.1f to wc -l\n' "$start" "$(echo "$start / $wc_t" | bc -l)"
printf 'lexing every number on 2 threads, nothing kept (bench/lex_floor.cpp): %.3f s, ratio %.1f to wc -l\n' \
  "$lex" "$(echo "$lex / $wc_t" | bc -l)"
printf 'writing %s moves, nothing parsed: %.3f s, ratio %.1f to wc -l (the floor for any reader of this Toolpath)\n' \
  "$lines" "$floor" "$(echo "$floor / $wc_t" | bc -l)"
printf 'ratio beadtwin / wc -l: %.1f\n' "$(echo "$bt / $wc_t" | bc -l)"
