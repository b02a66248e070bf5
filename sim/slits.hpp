// Filling the inside of the voids one voxel thin. A slit voxel is a voxel that is not solid between two
// solid voxels along some axis; it is filled when each of its six neighbours is solid or a slit voxel itself:
// the inside of a slit or a pipe one voxel across, not its mouth, nor the tip of a groove (one voxel deep,
// so its own mouth). Such a slit (a layer's interface under-filled along a wall, a gap between two passes, a
// seam's gap running up a wall) is a flaw of the bond, in the porosity the deposit reports; the voxels do
// not resolve its shape, so the comparison with the CAD (sim/cad_compare.hpp) takes it for no surface to
// machine or to measure from. Its mouth and the voids any thicker that open to the outside stay surface.
#pragma once

#include <openvdb/openvdb.h>

namespace beadtwin::sim {

// Sets the inside voxels of the slits of `fill` to 1 (active). A voxel is solid when its fill fraction is at
// least `solid_fill`. Precondition: no active tiles (voxelizeActiveTiles): the solid voxels are read one by
// one.
void fill_slits(openvdb::FloatGrid& fill, double solid_fill);

}  // namespace beadtwin::sim
