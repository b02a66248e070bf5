// Hand-made toolpaths of the patent's LSAM bead for the deposit's tests.
#pragma once

#include <algorithm>
#include <vector>

#include "core/bead.hpp"
#include "core/toolpath.hpp"
#include "core/units.hpp"

namespace beadtwin::testing {

// The LSAM bead of the patent: 0.83 in wide, 0.20 in tall after the roller.
constexpr double kBeadWidth = 0.83 * kMmPerInch;
constexpr double kBeadHeight = 0.20 * kMmPerInch;

// A fill bead from `from` to `to` under the roller, with the material of its flattened section.
inline Move bead(const Eigen::Vector3d& from, const Eigen::Vector3d& to, int layer = 0,
                 double width = kBeadWidth, double height = kBeadHeight) {
  Move m;
  m.start = from;
  m.end = to;
  m.kind = MoveKind::kPrint;
  m.feature = Feature::kFill;
  m.roller_down = true;
  m.feed_mm_s = 100.0;
  m.bead_width_mm = width;
  m.layer_height_mm = height;
  m.layer = layer;
  m.volume_mm3 = bead_area_mm2(width, height) * m.length_mm();
  return m;
}

inline Move travel(const Eigen::Vector3d& from, const Eigen::Vector3d& to, int layer = -1) {
  Move m;
  m.start = from;
  m.end = to;
  m.kind = MoveKind::kTravel;
  m.feature = Feature::kTravel;
  m.feed_mm_s = 400.0;
  m.layer = layer;
  return m;
}

// The moves with their layers (the LSAM bead's height each) and timed with the default motion limits.
inline Toolpath timed(std::vector<Move> moves) {
  Toolpath toolpath;
  toolpath.moves = std::move(moves);
  int layers = 0;
  for (const Move& m : toolpath.moves) layers = std::max(layers, m.layer + 1);
  toolpath.layers.resize(static_cast<std::size_t>(layers));
  for (std::size_t l = 0; l < toolpath.layers.size(); ++l) {
    toolpath.layers[l].z_mm = static_cast<double>(l + 1) * kBeadHeight;
    toolpath.layers[l].height_mm = kBeadHeight;
  }
  time_toolpath(toolpath, MotionLimits{});
  return toolpath;
}

// `count` beads of `length_mm` along x side by side at the pitch that fills the layer (A / h), `layers`
// high, each layer laid bead by bead from y = 0 with travels between them.
inline Toolpath bead_block(int count, int layers, double length_mm) {
  const double pitch = bead_area_mm2(kBeadWidth, kBeadHeight) / kBeadHeight;
  std::vector<Move> moves;
  Eigen::Vector3d at(0.0, 0.0, kBeadHeight);
  for (int l = 0; l < layers; ++l) {
    const double z = (l + 1) * kBeadHeight;
    for (int n = 0; n < count; ++n) {
      const Eigen::Vector3d a(0.0, n * pitch, z), b(length_mm, n * pitch, z);
      moves.push_back(travel(at, a));
      moves.push_back(bead(a, b, l));
      at = b;
    }
  }
  return timed(std::move(moves));
}

}  // namespace beadtwin::testing
