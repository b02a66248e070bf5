#!/usr/bin/env bash
# Installs the Debian 12 packages beadtwin builds with, if any are missing; with --tests, also what the test
# suite runs besides (tools/test.sh passes it). Plain apt-get as root, sudo otherwise. Safe to run again: it
# installs only what is missing.
set -euo pipefail

packages=(
  g++ cmake ninja-build pkg-config
  libeigen3-dev libfmt-dev libyaml-cpp-dev nlohmann-json3-dev libcli11-dev
  libtbb-dev libopenvdb-dev libboost-dev libboost-iostreams-dev libblosc-dev
  libembree-dev libopenimageio-dev libsundials-dev libpolyclipping-dev libassimp-dev
  libmeshoptimizer-dev libfreetype-dev libpng-dev fonts-dejavu-core
  libgtest-dev libgmock-dev libxml2-dev libjs-chart.js
  libopenmpi-dev openmpi-bin
)
# Not needed to build or run beadtwin: headless Chromium opens report.html in the browser tests
# (tests/scenarios/report_browser_test.cpp, skipped without it): 78 more packages on Debian 12, 138 MB to
# download, 459 MB installed. Clang with its sanitizer and libFuzzer runtimes (libclang-rt-14-dev) and
# llvm's symbolizer build and run the readers under the sanitizers and the fuzzer (tools/sanitize.sh).
# PrusaSlicer slices a box afresh for the reader's test against a peer slicer's program as that slicer
# writes it today (GcodeReaderPrusaSlicer.FreshlySlicedBoxReadsAsSliced, skipped without it): 27 more
# packages, 85 MB to download, 324 MB installed. (CuraEngine's test needs Cura's machine definitions too,
# which come only with the Qt front end: it stays skipped.) VTK's Python module reads the deposit's .vtu as
# ParaView does (DepositVtu.VtkReadsIt, skipped without it): 32 more packages, 41 MB to download, 225 MB
# installed.
test_packages=(chromium clang libclang-rt-14-dev llvm prusa-slicer python3-vtk9)

case "${1:-}" in
  "") ;;
  --tests) packages+=("${test_packages[@]}") ;;
  *)
    echo "usage: setup.sh [--tests]" >&2
    exit 2
    ;;
esac

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages are installed"
  exit 0
fi

if [ "$(id -u)" -eq 0 ]; then sudo=(); else sudo=(sudo); fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"
