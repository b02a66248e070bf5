# Sourced by the benchmark scripts: the repository's root, a scratch directory removed on exit, the median of
# numbers on standard input, and the steps the hull-mould benchmarks share.
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }

# build_bench BUILD_DIR TARGET: configures BUILD_DIR with the benchmarks and builds TARGET.
# (Debian's FindOpenVDB.cmake writes "COMPONENT = openvdb" to standard error at every configure: dropped.)
build_bench() {
  cmake -S "$root" -B "$1" -DBEADTWIN_BENCH=ON > /dev/null 2> >(grep -v '^COMPONENT = ' >&2)
  cmake --build "$1" --target "$2" > /dev/null
}

# write_hull_mould [DIR [LENGTH_MM WIDTH_MM HEIGHT_MM WALL_MM]]: the LSAM-scale hull-mould shell
# (bench/make_hull_mould.py, its default size unless given) and its scenario, in DIR (default $work).
write_hull_mould() {
  local dir="${1:-$work}"
  mkdir -p "$dir"
  python3 "$root/bench/make_hull_mould.py" "$dir/hull.stl" "${@:2}"
  cp "$root/bench/hull-mould.yaml" "$dir/"
}

# timed OUT CMD...: runs CMD (its output dropped, its errors kept in $work/stderr.txt), appends "seconds
# peak_MB" to OUT. Exit code 1 (a gate failed, as the default scenario's own gates do by design) is a
# finished run; above it the errors are shown and timed fails.
timed() {
  local out="$1" rc=0
  shift
  /usr/bin/time -f "%e %M" -o "$work/time.txt" "$@" > /dev/null 2> "$work/stderr.txt" || rc=$?
  if [ "$rc" -gt 1 ]; then
    cat "$work/stderr.txt" >&2
    return 1
  fi
  tail -1 "$work/time.txt" | awk '{printf "%s %.0f\n", $1, $2 / 1024}' >> "$out"
}

# The commit measured, "+changes" when the tree differs from it.
commit_id() { echo "$(git -C "$root" rev-parse --short HEAD)$(git -C "$root" diff --quiet HEAD || echo "+changes")"; }
