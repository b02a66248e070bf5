#include "sim/cad_field.hpp"

#include <cmath>
#include <vector>

#include <openvdb/tools/MeshToVolume.h>

#include "sim/nearest_triangles.hpp"
#include "sim/trilinear.hpp"

namespace beadtwin::sim {

// Points go to index space in double precision (the meshing's own world-space entry takes floats). Without
// OpenVDB's renormalization: it smooths the values near the surface for meshes that overlap themselves, and
// moves them off the true distance where a closed CAD turns a sharp corner (by more than half a voxel at an
// inside corner between a floor and a wall); without it, each value is the exact distance from the voxel's
// centre to the nearest triangle.
openvdb::FloatGrid::Ptr cad_distance_grid(const CadSurface& cad, const openvdb::math::Transform& transform,
                                          float band_voxels) {
  std::vector<openvdb::Vec3d> points;
  points.reserve(cad.vertices.size());
  for (const Eigen::Vector3d& v : cad.vertices)
    points.push_back(transform.worldToIndex(openvdb::Vec3d(v.x(), v.y(), v.z())));
  std::vector<openvdb::Vec3I> triangles;
  triangles.reserve(cad.triangles.size());
  for (const auto& t : cad.triangles)
    triangles.emplace_back(static_cast<openvdb::Index32>(t[0]), static_cast<openvdb::Index32>(t[1]),
                           static_cast<openvdb::Index32>(t[2]));
  const openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3d, openvdb::Vec3I> mesh(points, triangles);
  auto grid = openvdb::tools::meshToVolume<openvdb::FloatGrid>(mesh, transform, band_voxels, band_voxels,
                                                               openvdb::tools::DISABLE_RENORMALIZATION);
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  return grid;
}

struct CadField::Triangles {
  NearestTriangles nearest;
};

CadField::CadField(const CadSurface& cad, const openvdb::math::Transform& transform, double band_mm)
    : band_mm_(band_mm), voxel_mm_(transform.voxelSize()[0]) {
  grid_ = cad_distance_grid(cad, transform, static_cast<float>(narrow_voxels(band_mm, voxel_mm_)));
  std::vector<openvdb::Vec3s> points;
  points.reserve(cad.vertices.size());
  for (const Eigen::Vector3d& v : cad.vertices) points.emplace_back(openvdb::Vec3d(v.x(), v.y(), v.z()));
  std::vector<std::array<unsigned, 3>> triangles;
  triangles.reserve(cad.triangles.size());
  for (const auto& t : cad.triangles)
    triangles.push_back(
        {static_cast<unsigned>(t[0]), static_cast<unsigned>(t[1]), static_cast<unsigned>(t[2])});
  triangles_ = std::make_unique<const Triangles>(Triangles{NearestTriangles(points, triangles)});
}

CadField::~CadField() = default;

double CadField::at(const Eigen::Vector3d& point_mm) const {
  return at(grid_->getConstUnsafeAccessor(), point_mm);
}

double CadField::at(const openvdb::FloatGrid::ConstUnsafeAccessor& grid_accessor,
                    const Eigen::Vector3d& point_mm) const {
  // Within a voxel of the surface, every corner of the trilinear sample lies within the grid's band
  // (kNarrowVoxels = 2: a corner is at most √3/2 voxel further than the point).
  const double near = trilinear(grid_accessor, grid_->transform(), point_mm);
  if (std::abs(near) < voxel_mm_) return near;
  const NearestTriangles::Distance d = triangles_->nearest.distance(point_mm, band_mm_);
  return std::copysign(d.found ? d.mm : band_mm_, near);
}

}  // namespace beadtwin::sim
