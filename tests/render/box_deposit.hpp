// Hand-built deposits for the render tests, as a voxel model would hold them (fill fraction supersampled
// from the shape), without running sim::deposit: any shape, and a square box of walls, one bead per layer.
#pragma once

#include <algorithm>
#include <cmath>

#include <openvdb/openvdb.h>

#include "sim/deposit.hpp"

namespace beadtwin::render::testing {

struct BoxPart {
  double side_mm = 200.0;   // side of the square bead centreline; the box spans [0, side] in x and y
  double height_mm = 60.0;  // wall height (a whole number of layers is best)
  double bead_width_mm = 21.0;
  double layer_height_mm = 5.0;
  double voxel_mm = 2.5;
  double layer_time_s = 40.0;
  int supersample = 3;  // samples per voxel edge for the fill fraction
};

// Signed distance (xy) from the square centreline: outer corners come out round, as a bead laid around a
// corner does.
inline double distance_to_centreline(double x, double y, double side) {
  const double h = 0.5 * side;
  const double qx = std::abs(x - h) - h, qy = std::abs(y - h) - h;
  const double outside = std::hypot(std::max(qx, 0.0), std::max(qy, 0.0));
  return std::abs(outside + std::min(std::max(qx, qy), 0.0));
}

// Whether (s across the bead, t up from the bead's mid-height) is inside a stadium of width w, height h.
inline bool in_stadium(double s, double t, double w, double h) {
  const double r = 0.5 * h;
  const double dx = std::max(std::abs(s) - (0.5 * w - r), 0.0);
  return dx * dx + t * t <= r * r;
}

// A deposit of whatever `layer_at(x, y, z)` (mm) says: the layer of the material at a point, or -1 for
// none. Voxels of `voxel_mm` on the deposit's transform over the world box [lo, hi]; each voxel's fill is
// the fraction of its n^3 samples with material, its layer the highest layer sampled in it.
// `column_may_hold(x, y)` may skip the columns of voxels (centres x, y) that surely hold nothing.
struct AnyColumn {
  bool operator()(double, double) const { return true; }
};
template <class LayerAt, class ColumnMayHold = AnyColumn>
sim::Deposit voxelise(const LayerAt& layer_at, const openvdb::Vec3d& lo, const openvdb::Vec3d& hi,
                      double voxel_mm, int n = 3, double layer_time_s = 40.0,
                      const ColumnMayHold& column_may_hold = {}) {
  const double vs = voxel_mm;
  const auto transform = sim::deposit_transform(vs);  // the deposit's documented convention
  sim::Deposit d;
  d.voxel_size_mm = vs;
  d.fill = openvdb::FloatGrid::create(0.0f);
  d.time = openvdb::FloatGrid::create(0.0f);
  d.layer = openvdb::Int32Grid::create(-1);
  d.fill->setTransform(transform);
  d.time->setTransform(transform);
  d.layer->setTransform(transform);
  const openvdb::Coord first = transform->worldToIndexCellCentered(lo);
  const openvdb::Coord last = transform->worldToIndexCellCentered(hi);
  auto fill = d.fill->getAccessor();
  auto time = d.time->getAccessor();
  auto layer = d.layer->getAccessor();
  for (int i = first.x(); i <= last.x(); ++i)
    for (int j = first.y(); j <= last.y(); ++j) {
      const openvdb::Vec3d column = transform->indexToWorld(openvdb::Coord(i, j, 0));
      if (!column_may_hold(column.x(), column.y())) continue;
      for (int k = first.z(); k <= last.z(); ++k) {
        const openvdb::Coord ijk(i, j, k);
        const openvdb::Vec3d centre = transform->indexToWorld(ijk);
        int inside = 0, top_layer = -1;
        for (int a = 0; a < n; ++a)
          for (int b = 0; b < n; ++b)
            for (int c = 0; c < n; ++c) {
              const int l =
                  layer_at(centre.x() + ((a + 0.5) / n - 0.5) * vs, centre.y() + ((b + 0.5) / n - 0.5) * vs,
                           centre.z() + ((c + 0.5) / n - 0.5) * vs);
              if (l < 0) continue;
              ++inside;
              top_layer = std::max(top_layer, l);
            }
        if (inside == 0) continue;
        const float f = static_cast<float>(inside) / static_cast<float>(n * n * n);
        fill.setValue(ijk, f);
        layer.setValue(ijk, top_layer);
        time.setValue(ijk, static_cast<float>((top_layer + 1) * layer_time_s));
        d.deposited_volume_mm3 += f * vs * vs * vs;
      }
    }
  d.active_voxels = d.fill->activeVoxelCount();
  d.commanded_volume_mm3 = d.deposited_volume_mm3;
  d.swept_volume_mm3 = d.deposited_volume_mm3;
  return d;
}

inline sim::Deposit make_box_deposit(const BoxPart& part = {}) {
  const int layers = static_cast<int>(std::lround(part.height_mm / part.layer_height_mm));
  const double half_w = 0.5 * part.bead_width_mm, margin = half_w + part.voxel_mm;
  const auto layer_at = [&](double x, double y, double z) {
    if (distance_to_centreline(x, y, part.side_mm) > half_w) return -1;  // quick reject
    const int l = static_cast<int>(std::floor(z / part.layer_height_mm));
    if (l < 0 || l >= layers) return -1;
    const double t = z - (l + 0.5) * part.layer_height_mm;
    return in_stadium(distance_to_centreline(x, y, part.side_mm), t, part.bead_width_mm, part.layer_height_mm)
               ? l
               : -1;
  };
  const openvdb::Vec3d lo(-margin, -margin, -part.voxel_mm);
  const openvdb::Vec3d hi(part.side_mm + margin, part.side_mm + margin,
                          layers * part.layer_height_mm + part.voxel_mm);
  const auto near_wall = [&](double x, double y) {
    return distance_to_centreline(x, y, part.side_mm) <= half_w + part.voxel_mm;
  };
  return voxelise(layer_at, lo, hi, part.voxel_mm, part.supersample, part.layer_time_s, near_wall);
}

// A deposit with grids but nothing in them.
inline sim::Deposit make_empty_deposit(double voxel_mm = 2.5) {
  sim::Deposit d;
  d.voxel_size_mm = voxel_mm;
  const auto transform = sim::deposit_transform(voxel_mm);
  d.fill = openvdb::FloatGrid::create(0.0f);
  d.fill->setTransform(transform);
  d.time = openvdb::FloatGrid::create(0.0f);
  d.time->setTransform(transform);
  d.layer = openvdb::Int32Grid::create(-1);
  d.layer->setTransform(transform);
  return d;
}

}  // namespace beadtwin::render::testing
