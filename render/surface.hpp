// The deposit's surface as the renderer sees it: the fill-fraction isosurface as a triangle mesh (the part
// as printed, bead ridges and all), and the toolpath layer of the material under any point of it.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <openvdb/openvdb.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace beadtwin::render {

// The deposit's surface as triangles, with a normal at every point.
struct SurfaceMesh {
  std::vector<Eigen::Vector3f> points;   // world (machine frame), mm
  std::vector<Eigen::Vector3f> normals;  // per point, unit, area-weighted average of the faces around it;
                                         // consistently oriented, but callers face them to the viewer
  std::vector<std::array<std::uint32_t, 3>> triangles;
  // The last 2 * quads triangles are the mesher's quads, each cut in two along its shorter diagonal and
  // written as Embree cuts a quad: a, b, c, d as (a, b, d), (c, d, b). The ray-tracing scene takes them as
  // quads (half as many primitives to build its hierarchy over), the triangles before them each as a quad
  // of its own; primitive_hit gives the triangle a hit on a primitive lies on.
  std::size_t quads = 0;
  Eigen::AlignedBox3f bounds;  // of the points
};

// The isosurface of `fill` at `isovalue` (fill fraction 0..1), in world coordinates through the grid's
// transform; quads are split along their shorter diagonal. Throws InputError("nothing was deposited: ...")
// when the grid has no active voxels or no surface at `isovalue`.
SurfaceMesh extract_surface(const openvdb::FloatGrid& fill, double isovalue = 0.5);

// The same from the mesher's polygons (of a grid with `active_voxels` active voxels, meshed at `isovalue`
// with adaptivity 0), as sim::mesh_fill gives them: a surface meshed once for the skin and the pictures.
SurfaceMesh surface_mesh(const std::vector<openvdb::Vec3s>& points,
                         const std::vector<openvdb::Vec3I>& triangles,
                         const std::vector<openvdb::Vec4I>& quads, openvdb::Index64 active_voxels,
                         double isovalue = 0.5);

// A hit on the ray-tracing scene's primitive p (the lone triangles first, then the quads: SurfaceMesh::quads)
// at Embree's quad coordinates (u, v), as a hit on one of `mesh`'s triangles at that triangle's barycentric
// coordinates (u: the weight of its second corner, v: its third).
struct TriangleHit {
  std::uint32_t triangle = 0;
  float u = 0.0f, v = 0.0f;
};
inline TriangleHit primitive_hit(const SurfaceMesh& mesh, std::uint32_t p, float u, float v) {
  const auto lone = static_cast<std::uint32_t>(mesh.triangles.size() - 2 * mesh.quads);
  if (p < lone) return {p, u, v};  // a, b, c, c: only its first half, a, b, c, has area
  // Embree's quad a, b, c, d is the triangles (a, b, d) at (u, v) and (c, d, b) at (1 - u, 1 - v).
  const std::uint32_t first = lone + 2 * (p - lone);
  if (u + v <= 1.0f) return {first, u, v};
  return {first + 1, 1.0f - u, 1.0f - v};
}

// Finds the layer of the material just inside a surface point. One per thread (it caches grid nodes), and
// only while the grid does not change: its accessor is not registered with the tree (a registration per
// tile, in a table every thread shares, costs more than it saves, and trips UndefinedBehaviorSanitizer in
// TBB's table when the tree goes).
class LayerProbe {
 public:
  explicit LayerProbe(const openvdb::Int32Grid& layer);

  // The layer index of the voxel half a voxel inside `point` (world, mm) along `inward` (unit): that
  // voxel if it holds material, else the nearest voxel with material in its 3x3x3 neighbourhood, else -1.
  int layer_at(const Eigen::Vector3f& point, const Eigen::Vector3f& inward);

 private:
  openvdb::Int32Grid::ConstUnsafeAccessor accessor_;
  const openvdb::math::Transform& transform_;
  double half_voxel_mm_;
};

// Finds the value of a field (a float grid active on the material voxels) just inside a surface point, as
// LayerProbe finds the layer. One per thread.
class FieldProbe {
 public:
  explicit FieldProbe(const openvdb::FloatGrid& field);

  // The value of the active voxel half a voxel inside `point` along `inward`, else of the nearest active
  // voxel in its 3x3x3 neighbourhood, else NaN. An active voxel's value is taken as it is (NaN included).
  float value_at(const Eigen::Vector3f& point, const Eigen::Vector3f& inward);
  // The voxel whose value value_at takes, or none (NaN). It depends on the grid's active voxels only, so it
  // is the voxel of any field active on the same voxels (TracedPicture).
  std::optional<openvdb::Coord> voxel_at(const Eigen::Vector3f& point, const Eigen::Vector3f& inward);

 private:
  openvdb::FloatGrid::ConstUnsafeAccessor accessor_;
  const openvdb::math::Transform& transform_;
  double half_voxel_mm_;
};

}  // namespace beadtwin::render
