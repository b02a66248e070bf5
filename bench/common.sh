# Sourced by the benchmark scripts: the repository's root, a scratch directory removed on exit, the median of
# numbers on standard input, and the steps the hull-mould benchmarks share.
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }

# build_bench BUILD_DIR TARGET: configures BUILD_DIR with the benchmarks and builds TARGET.
build_bench() {
  cmake -S "$root" -B "$1" -DBEADTWIN_BENCH=ON > /dev/null
  cmake --build "$1" --target "$2" > /dev/null
}

# The LSAM-scale hull-mould shell (bench/make_hull_mould.py) and its scenario, in $work.
write_hull_mould() {
  python3 "$root/bench/make_hull_mould.py" "$work/hull.stl"
  cp "$root/bench/hull-mould.yaml" "$work/"
}
