// The least any reader of a program must spend to hand over its Toolpath: N moves written into a vector
// reserved as the reader reserves it (in huge pages where the system has them, core/memory.hpp), with
// nothing parsed. bench/read_vs_wc.sh compiles it on the fly and runs it with the program's
// line count, so the floor is measured in the same run as `wc -l` and `beadtwin read`.
// Usage: toolpath_floor MOVES   (prints the wall time in seconds)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "core/memory.hpp"
#include "core/toolpath.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: toolpath_floor MOVES\n");
    return 2;
  }
  const auto n = static_cast<std::size_t>(std::strtoull(argv[1], nullptr, 10));
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<beadtwin::Move> moves;
  beadtwin::reserve_huge(moves, n);
  Eigen::Vector3d at = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    beadtwin::Move m;
    m.start = at;
    at.x() += 1.0 + static_cast<double>(i & 7);
    m.end = at;
    m.feed_mm_s = 30.0;
    m.volume_mm3 = 0.1 * static_cast<double>(i & 15);
    m.layer = static_cast<int>(i >> 12);
    m.source_line = static_cast<int>(i);
    moves.push_back(m);
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  double volume = 0.0;  // read back, so the writes cannot be optimised away
  for (const beadtwin::Move& m : moves) volume += m.volume_mm3;
  std::printf("%.4f\n", volume > 0.0 ? s : -1.0);
  return 0;
}
