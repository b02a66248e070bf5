// A block of full voxels for the sim tests' hand-made deposits.
#pragma once

#include <openvdb/openvdb.h>

#include "sim/deposit.hpp"

namespace beadtwin::testing {

// Fill 1 in voxels (i, j, k) with 0 <= i < size.x(), 0 <= j < size.y(), 0 <= k < size.z(), on the deposit's
// voxels of `voxel_mm` (sim::deposit_transform): the block spans [0, size · voxel_mm) along each axis.
inline openvdb::FloatGrid::Ptr full_block(const openvdb::Coord& size, double voxel_mm = 1.0) {
  openvdb::FloatGrid::Ptr fill = openvdb::FloatGrid::create(0.0f);
  fill->setTransform(sim::deposit_transform(voxel_mm));
  auto acc = fill->getAccessor();
  for (int k = 0; k < size.z(); ++k)
    for (int j = 0; j < size.y(); ++j)
      for (int i = 0; i < size.x(); ++i) acc.setValue({i, j, k}, 1.0f);
  return fill;
}

}  // namespace beadtwin::testing
