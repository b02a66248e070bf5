#!/usr/bin/env bash
# The readers under the sanitizers and the fuzzer (docs/RELIABILITY.md): builds with Clang,
# AddressSanitizer, UndefinedBehaviorSanitizer and libFuzzer's coverage the libraries that read users' files
# (BEADTWIN_READERS_ONLY: core, gcode, slicer, the scenario files), their test suites and the fuzz targets in
# tests/fuzz, then runs them all under ctest: the tests, every seed and past crash once, and
# BEADTWIN_FUZZ_SECONDS (default 30) of fuzzing per target. tools/test.sh runs it after the main suite.
#
#   tools/sanitize.sh            build in build-sanitize/ (BEADTWIN_SANITIZE_DIR) and run
#   BEADTWIN_FUZZ_SECONDS=600 tools/sanitize.sh   the documented longer run
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BEADTWIN_SANITIZE_DIR:-$root/build-sanitize}"
seconds="${BEADTWIN_FUZZ_SECONDS:-30}"

mkdir -p "$build"
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DBEADTWIN_READERS_ONLY=ON -DBEADTWIN_FUZZ=ON -DBEADTWIN_SANITIZE=address,undefined \
  -DBEADTWIN_FUZZ_SECONDS="$seconds" -DBEADTWIN_WERROR=ON >"$build/configure.log" 2>&1 || {
  cat "$build/configure.log"
  exit 1
}
cmake --build "$build"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# LSAN_OPTIONS (the suppressions) is set per test by tests/CMakeLists.txt.
cd "$build"
ctest --output-on-failure -j "$(nproc)"
