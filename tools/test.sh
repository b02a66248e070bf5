#!/usr/bin/env bash
# Quick start, second command: install what is missing, build (Release, warnings as errors) and run the
# whole test suite under ctest; then the readers' suites and fuzz targets under the sanitizers
# (tools/sanitize.sh, a second build with Clang).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BEADTWIN_BUILD_DIR:-$root/build}"

bash "$root/tools/setup.sh" --tests
mkdir -p "$build"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DBEADTWIN_BUILD_TESTS=ON -DBEADTWIN_WERROR=ON >"$build/configure.log" 2>&1 || {
  cat "$build/configure.log"
  exit 1
}
cmake --build "$build"
cd "$build"
ctest --output-on-failure -j "$(nproc)"
BEADTWIN_SANITIZE_DIR="${BEADTWIN_SANITIZE_DIR:-$build-sanitize}" bash "$root/tools/sanitize.sh"
