#include "sim/substrate.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/geometry.hpp"

namespace beadtwin::sim {

namespace {

// A voxel this close to full has no gap worth filling.
constexpr double kFullEnough = 1e-3;
// A voxel this full seals the gaps under it from the bead above.
constexpr double kSealed = 0.95;

}  // namespace

Substrate measure_substrate(const BeadSweep& sweep, double top_mm, double height_mm, double reach_mm,
                            const openvdb::FloatGrid& fill, double voxel_size_mm, double table_z_mm,
                            int highest_k) {
  BT_CHECK_OP(voxel_size_mm, >, 0.0);
  BT_CHECK_OP(height_mm, >, 0.0);
  const double s = voxel_size_mm;
  const double bottom = top_mm - height_mm;
  const double half_width = 0.5 * sweep.profile.width_mm();
  const Eigen::Vector2d lo = sweep.start_xy.cwiseMin(sweep.end_xy).array() - half_width;
  const Eigen::Vector2d hi = sweep.start_xy.cwiseMax(sweep.end_xy).array() + half_width;
  const int i0 = static_cast<int>(std::floor(lo.x() / s)), i1 = static_cast<int>(std::floor(hi.x() / s));
  const int j0 = static_cast<int>(std::floor(lo.y() / s)), j1 = static_cast<int>(std::floor(hi.y() / s));
  // Voxels whose centres lie in [bottom - h, top + h).
  const int k0 = static_cast<int>(std::ceil((bottom - height_mm) / s - 0.5));
  // Above the deposit's highest material and the table every voxel is empty and adds nothing: the roller's
  // reach (half its diameter, 19 voxels on the LSAM at 2 mm) is mostly air not yet printed.
  const int k_table = static_cast<int>(std::ceil(table_z_mm / s - 0.5));  // the first voxel centred above it
  const int k1 = std::min(static_cast<int>(std::ceil((top_mm + std::max(height_mm, reach_mm)) / s - 0.5)),
                          std::max(highest_k + 1, k_table));
  const int k_bottom = static_cast<int>(std::ceil(bottom / s - 0.5));  // the first voxel centred above it
  auto acc = fill.getConstAccessor();
  Substrate out;
  out.supported = 0.0;
  const auto fill_at = [&](int i, int j, int k) {
    return (k + 0.5) * s < table_z_mm ? 1.0
                                      : std::clamp<double>(acc.getValue(openvdb::Coord(i, j, k)), 0.0, 1.0);
  };
  // A gap between beads has material on both sides of it, across the bead, within a bead width; the notch
  // outside a wall's rounded flank does not (the new bead bulges over it, but it stays: the layer lines).
  const Eigen::Vector2d along = sweep.end_xy - sweep.start_xy;
  const Eigen::Vector2d across =
      along.norm() > 0.0 ? Eigen::Vector2d(-along.y(), along.x()).normalized() : Eigen::Vector2d(1.0, 0.0);
  const int reach = std::max(1, static_cast<int>(std::ceil(2.0 * half_width / s)));
  const auto between_beads = [&](int i, int j, int k) {
    const Eigen::Vector2d c((i + 0.5) * s, (j + 0.5) * s);
    for (const double side : {-1.0, 1.0}) {
      bool found = false;
      for (int step = 1; step <= reach && !found; ++step) {
        const Eigen::Vector2d p = c + side * step * s * across;
        found = fill_at(static_cast<int>(std::floor(p.x() / s)), static_cast<int>(std::floor(p.y() / s)),
                        k) >= 0.5;
      }
      if (!found) return false;
    }
    return true;
  };
  const auto column = [&](int i, int j) {
    double gap = 0.0, above = 0.0, over = 0.0;
    bool supported = bottom - height_mm < table_z_mm + 0.5 * s;
    for (int k = k0; k < k1; ++k) {
      const double z = (k + 0.5) * s;
      const double f = fill_at(i, j, k);
      if (z < bottom) {
        supported = supported || f > 0.0;
      } else if (z < top_mm) {
        above += f * s;
      } else {
        over += f * s;
      }
    }
    // The gaps the bead can reach: down from its bottom, until solid material seals what lies deeper (the
    // cusps under the beads below, against the table or the layer before, are out of reach).
    for (int k = k_bottom - 1; k >= k0; --k) {
      const double f = fill_at(i, j, k);
      if (f >= kSealed || !between_beads(i, j, k)) break;
      gap += (1.0 - f) * s;
      if (f < 1.0 - kFullEnough)
        out.gap_cells.push_back({openvdb::Coord(i, j, k), static_cast<float>(1.0 - f), 0.5f});
    }
    out.gap_mm += gap;
    out.above_mm += above;
    out.over_top_mm += over;
    out.supported += supported ? 1.0 : 0.0;
    ++out.columns;
  };
  for (int i = i0; i <= i1; ++i)
    for (int j = j0; j <= j1; ++j) {
      const Eigen::Vector2d c((i + 0.5) * s, (j + 0.5) * s);
      if (distance_to_segment(c, sweep.start_xy, sweep.end_xy) <= half_width) column(i, j);
    }
  if (out.columns == 0) {
    const Eigen::Vector2d mid = 0.5 * (sweep.start_xy + sweep.end_xy);
    column(static_cast<int>(std::floor(mid.x() / s)), static_cast<int>(std::floor(mid.y() / s)));
  }
  const double n = out.columns;
  out.gap_mm /= n;
  out.above_mm /= n;
  out.over_top_mm /= n;
  out.supported /= n;
  return out;
}

}  // namespace beadtwin::sim
