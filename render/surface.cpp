#include "render/surface.hpp"

#include <limits>
#include <optional>
#include <string>

#include <openvdb/tools/VolumeToMesh.h>

#include "core/error.hpp"

namespace beadtwin::render {

namespace {

Eigen::Vector3f to_eigen(const openvdb::Vec3s& v) {
  return {v.x(), v.y(), v.z()};
}

// Two triangles per quad, cut along the shorter diagonal (on a bent quad that follows the surface better),
// in Embree's layout (SurfaceMesh::quads): the quad started at the corner before the diagonal's first end.
void add_quad(const openvdb::Vec4I& q, const std::vector<Eigen::Vector3f>& points,
              std::vector<std::array<std::uint32_t, 3>>& triangles) {
  const float d02 = (points[q[0]] - points[q[2]]).squaredNorm();
  const float d13 = (points[q[1]] - points[q[3]]).squaredNorm();
  const int s = d02 <= d13 ? 1 : 0;  // a = q[s]; the cut runs from b = q[s + 1] to d = q[s + 3]
  const auto at = [&](int k) { return q[(s + k) % 4]; };
  triangles.push_back({at(0), at(1), at(3)});
  triangles.push_back({at(2), at(3), at(1)});
}

void compute_normals(SurfaceMesh& mesh) {
  mesh.normals.assign(mesh.points.size(), Eigen::Vector3f::Zero());
  for (const auto& t : mesh.triangles) {
    // Unnormalised cross product: its length is twice the area, so big faces weigh more.
    const Eigen::Vector3f n =
        (mesh.points[t[1]] - mesh.points[t[0]]).cross(mesh.points[t[2]] - mesh.points[t[0]]);
    for (const std::uint32_t i : t) mesh.normals[i] += n;
  }
  for (auto& n : mesh.normals) {
    const float length = n.norm();
    n = length > 0.0f ? Eigen::Vector3f(n / length) : Eigen::Vector3f::UnitZ();
  }
}

}  // namespace

SurfaceMesh extract_surface(const openvdb::FloatGrid& fill, double isovalue) {
  const openvdb::Index64 active = fill.activeVoxelCount();
  if (active == 0) throw InputError("nothing was deposited: the fill grid has no active voxels");
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(fill, points, triangles, quads, isovalue, /*adaptivity=*/0.0);
  return surface_mesh(points, triangles, quads, active, isovalue);
}

SurfaceMesh surface_mesh(const std::vector<openvdb::Vec3s>& points,
                         const std::vector<openvdb::Vec3I>& triangles,
                         const std::vector<openvdb::Vec4I>& quads, openvdb::Index64 active_voxels,
                         double isovalue) {
  SurfaceMesh mesh;
  mesh.points.reserve(points.size());
  for (const auto& p : points) mesh.points.push_back(to_eigen(p));
  mesh.triangles.reserve(triangles.size() + 2 * quads.size());
  for (const auto& t : triangles) mesh.triangles.push_back({t[0], t[1], t[2]});
  for (const auto& q : quads) add_quad(q, mesh.points, mesh.triangles);
  mesh.quads = quads.size();
  for (const auto& p : mesh.points) mesh.bounds.extend(p);

  if (mesh.triangles.empty() || mesh.bounds.isEmpty() || (mesh.bounds.sizes().array() <= 0.0f).any())
    throw InputError("nothing was deposited: the fill grid's " + std::to_string(active_voxels) +
                     " active voxels have no surface at fill fraction " + std::to_string(isovalue) +
                     " (is every voxel less than " + std::to_string(isovalue) + " full?)");
  compute_normals(mesh);
  return mesh;
}

namespace {

// The voxel half a voxel inside `point` along `inward` if `holds` accepts it (an active voxel and its
// value), else the nearest accepted voxel in its 3x3x3 neighbourhood (the step landed in a void or outside:
// thin features, corners), else none; its value in `value`.
template <class Accessor, class Value, class Holds>
std::optional<openvdb::Coord> probe(Accessor& accessor, const openvdb::math::Transform& transform,
                                    double half_voxel_mm, const Eigen::Vector3f& point,
                                    const Eigen::Vector3f& inward, Value& value, const Holds& holds) {
  const Eigen::Vector3d inside = point.cast<double>() + half_voxel_mm * inward.cast<double>();
  const openvdb::Vec3d index = transform.worldToIndex(openvdb::Vec3d(inside.x(), inside.y(), inside.z()));
  const openvdb::Coord centre = openvdb::Coord::round(index);
  if (accessor.probeValue(centre, value) && holds(value)) return centre;
  std::optional<openvdb::Coord> best;
  Value best_value = value;
  double best_distance = std::numeric_limits<double>::max();
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const openvdb::Coord c = centre.offsetBy(dx, dy, dz);
        if (!accessor.probeValue(c, value) || !holds(value)) continue;
        const double distance = (c.asVec3d() - index).lengthSqr();
        if (distance < best_distance) {
          best_distance = distance;
          best = c;
          best_value = value;
        }
      }
  value = best_value;
  return best;
}

}  // namespace

LayerProbe::LayerProbe(const openvdb::Int32Grid& layer)
    : accessor_(layer.getConstUnsafeAccessor()),
      transform_(layer.transform()),
      half_voxel_mm_(0.5 * layer.voxelSize()[0]) {}

int LayerProbe::layer_at(const Eigen::Vector3f& point, const Eigen::Vector3f& inward) {
  // Material is an active voxel with a layer (>= 0).
  int layer = -1;
  return probe(accessor_, transform_, half_voxel_mm_, point, inward, layer, [](int v) { return v >= 0; })
             ? layer
             : -1;
}

FieldProbe::FieldProbe(const openvdb::FloatGrid& field)
    : accessor_(field.getConstUnsafeAccessor()),
      transform_(field.transform()),
      half_voxel_mm_(0.5 * field.voxelSize()[0]) {}

// Material is an active voxel, whatever its value (NaN: material without a value).
float FieldProbe::value_at(const Eigen::Vector3f& point, const Eigen::Vector3f& inward) {
  float value = 0.0f;
  return probe(accessor_, transform_, half_voxel_mm_, point, inward, value, [](float) { return true; })
             ? value
             : std::numeric_limits<float>::quiet_NaN();
}

std::optional<openvdb::Coord> FieldProbe::voxel_at(const Eigen::Vector3f& point,
                                                   const Eigen::Vector3f& inward) {
  float value = 0.0f;
  return probe(accessor_, transform_, half_voxel_mm_, point, inward, value, [](float) { return true; });
}

}  // namespace beadtwin::render
