// A grid's value at a point in the machine frame, trilinear between voxel centres (OpenVDB's BoxSampler),
// reading through an accessor the caller keeps (one per thread).
#pragma once

#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#include <Eigen/Core>

namespace beadtwin::sim {

// `accessor`: any OpenVDB accessor of the grid; `transform`: the grid's; `point_mm`: machine frame, mm.
// Returns the grid's value type as a double.
template <class Accessor>
double trilinear(const Accessor& accessor, const openvdb::math::Transform& transform,
                 const Eigen::Vector3d& point_mm) {
  return openvdb::tools::BoxSampler::sample(
      accessor, transform.worldToIndex(openvdb::Vec3d(point_mm.x(), point_mm.y(), point_mm.z())));
}

}  // namespace beadtwin::sim
