// A deposited box for the tests of the deposit's files: a square ring of beads laid layer on layer by
// sim::deposit from a hand-made toolpath, as a thin-walled open box prints; and what those tests share for
// reading the files back.
#pragma once

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "core/bead.hpp"
#include "core/toolpath.hpp"
#include "sim/deposit.hpp"

namespace beadtwin::sim::testing {

struct Ring {
  double side_mm = 120.0;  // the bead centreline is the square [0, side]²
  double bead_width_mm = 20.0;
  double layer_height_mm = 5.0;
  int layers = 4;
  double voxel_mm = 2.5;
};

inline Move ring_bead(const Eigen::Vector3d& from, const Eigen::Vector3d& to, int layer, const Ring& r) {
  Move m;
  m.start = from;
  m.end = to;
  m.kind = MoveKind::kPrint;
  m.feature = Feature::kBoundary;
  m.pass = 0;
  m.roller_down = true;
  m.feed_mm_s = 100.0;
  m.bead_width_mm = r.bead_width_mm;
  m.layer_height_mm = r.layer_height_mm;
  m.layer = layer;
  m.volume_mm3 = bead_area_mm2(r.bead_width_mm, r.layer_height_mm) * m.length_mm();
  return m;
}

// Each layer one closed loop of four beads; timed with the default motion limits.
inline Toolpath ring_toolpath(const Ring& r = {}) {
  Toolpath tp;
  for (int l = 0; l < r.layers; ++l) {
    const double z = (l + 1) * r.layer_height_mm, s = r.side_mm;
    const Eigen::Vector3d corners[] = {{0, 0, z}, {s, 0, z}, {s, s, z}, {0, s, z}};
    for (int c = 0; c < 4; ++c) tp.moves.push_back(ring_bead(corners[c], corners[(c + 1) % 4], l, r));
  }
  tp.layers.resize(static_cast<std::size_t>(r.layers));
  time_toolpath(tp, MotionLimits{});
  return tp;
}

inline Deposit ring_deposit(const Ring& r = {}) {
  DepositOptions o;
  o.voxel_size_mm = r.voxel_mm;
  return deposit(ring_toolpath(r), o);
}

// A deposit with grids but nothing in them.
inline Deposit empty_deposit(double voxel_mm = 2.5) {
  DepositOptions o;
  o.voxel_size_mm = voxel_mm;
  return deposit(Toolpath{}, o);
}

// The ring deposit, made once for every test that only reads it.
inline const Deposit& ring() {
  static const Deposit d = ring_deposit();
  return d;
}

// An empty folder under the system's temporary one, named for the test (names must differ between tests,
// which may run at the same time).
inline std::filesystem::path fresh_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("beadtwin_sim_test_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// A value of type T read from `bytes` at offset `at`, as the file stores it (little-endian).
template <class T>
T get(const std::string& bytes, std::size_t at) {
  T v;
  std::memcpy(&v, bytes.data() + at, sizeof v);
  return v;
}

}  // namespace beadtwin::sim::testing
