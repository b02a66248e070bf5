// The CAD's signed distance (mm, negative inside) on the deposit's voxels, out to a band (the reach of the
// stock) and ±band beyond it: what the comparison with the CAD measures the printed skin by, and what the
// deviation pictures colour it by (sim/cad_compare.hpp).
//
// Two parts: a narrow-band distance grid on the deposit's voxels, kNarrowVoxels either side of the CAD
// (OpenVDB's mesh-to-volume: exact distances at the voxel centres there, and inside and outside told by a
// flood of the sign everywhere, whatever the triangles' winding), and the CAD's triangles in an Embree
// scene (sim/nearest_triangles.hpp). Within a voxel of the CAD's surface (by the grid) the distance is the
// grid's, trilinear between voxel centres; further out it is the exact distance to the nearest triangle,
// with the grid's sign. A grid as wide as the whole band would cost far more on a large part: most of the
// skin lies within a voxel or two of the CAD, and the few points further out are cheaper to query exactly.
#pragma once

#include <algorithm>
#include <array>
#include <memory>
#include <span>

#include <openvdb/openvdb.h>
#include <Eigen/Core>

namespace beadtwin::sim {

// The part's CAD in the machine frame, mm: a closed triangle mesh (its winding does not matter; inside and
// outside come from the surface itself). Plain vertices and triangles, so the simulation needs nothing of
// the slicer.
struct CadSurface {
  std::span<const Eigen::Vector3d> vertices;
  std::span<const std::array<int, 3>> triangles;  // indices into vertices
};

// Safe to call from several threads at once.
class CadField {
 public:
  static constexpr double kNarrowVoxels = 2.0;
  // Half-width of the distance grid, voxels: kNarrowVoxels, within the band.
  static double narrow_voxels(double band_mm, double voxel_mm) {
    return std::min(kNarrowVoxels, band_mm / voxel_mm);
  }

  // `cad`: every vertex finite, every index in range, some area (compare_with_cad checks them).
  // `transform`: the deposit's (deposit_transform), its voxel size in mm. `band_mm`: the reach, from 2 to
  // 256 voxels.
  CadField(const CadSurface& cad, const openvdb::math::Transform& transform, double band_mm);
  ~CadField();
  CadField(const CadField&) = delete;
  CadField& operator=(const CadField&) = delete;

  // The signed distance at `point_mm` (machine frame), mm: exact to the nearest triangle beyond a voxel of
  // the surface, ±band beyond the band.
  double at(const Eigen::Vector3d& point_mm) const;
  // The same, reading the grid through `grid_accessor` (one per thread, from grid()).
  double at(const openvdb::FloatGrid::ConstUnsafeAccessor& grid_accessor,
            const Eigen::Vector3d& point_mm) const;
  // The narrow band: exact within kNarrowVoxels of the CAD, ±kNarrowVoxels voxels beyond, signed everywhere.
  const openvdb::FloatGrid& grid() const { return *grid_; }

 private:
  struct Triangles;  // in Embree
  openvdb::FloatGrid::Ptr grid_;
  std::unique_ptr<const Triangles> triangles_;
  double band_mm_ = 0.0, voxel_mm_ = 0.0;
};

// The CAD's signed distance on the voxels of `transform` (mm), `band_voxels` either side of its surface,
// exact at every voxel centre within it and ±band_voxels voxels (in mm) beyond, signed by a flood
// whatever the triangles' winding. Preconditions as for CadField.
openvdb::FloatGrid::Ptr cad_distance_grid(const CadSurface& cad, const openvdb::math::Transform& transform,
                                          float band_voxels);

}  // namespace beadtwin::sim
