#include "sim/travel_collision.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Core>

#include "sim/deposit.hpp"

namespace beadtwin::sim {

double travel_collision_mm(const Move& move, const openvdb::FloatGrid& fill, double voxel_size_mm,
                           double nozzle_diameter_mm) {
  const double s = voxel_size_mm;
  const double length = move.length_mm();
  const int steps = std::max(1, static_cast<int>(std::ceil(length / s)));
  auto acc = fill.getConstAccessor();
  const double r = 0.5 * nozzle_diameter_mm;
  const std::array<Eigen::Vector2d, 5> offsets = {Eigen::Vector2d(0, 0), {r, 0}, {-r, 0}, {0, r}, {0, -r}};
  double deepest = 0.0;
  for (int t = 0; t <= steps; ++t) {
    const Eigen::Vector3d p = move.start + (move.end - move.start) * (static_cast<double>(t) / steps);
    const int k_tip = voxel_row_at_or_above(p.z() + 0.5 * s, s);  // a voxel clearly above the tip
    for (const Eigen::Vector2d& o : offsets) {
      if (r <= 0.0 && o != Eigen::Vector2d::Zero()) break;
      const openvdb::Coord ij = voxel_containing({p.x() + o.x(), p.y() + o.y(), p.z()}, s);
      for (int k = k_tip; k < k_tip + 4; ++k)
        if (acc.getValue(openvdb::Coord(ij.x(), ij.y(), k)) >= 0.5f)
          deepest = std::max(deepest, (k + 1) * s - p.z());
    }
  }
  return deepest;
}

}  // namespace beadtwin::sim
