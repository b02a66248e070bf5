// Filling the voids a solid closes in: the empty voxels of a box that no path of face-neighbouring empty
// voxels joins to the box's open sides. The comparison with the CAD fills them (sim/cad_compare.hpp): they
// are porosity, which the deposit reports, not surface, so their walls must not count as the printed skin or
// bound a stock.
//
// A flood from the box's open sides over a dense bit per voxel, row by row along x (each row's bits in whole
// 64-bit words): a row's free runs that hold a reached voxel are reached whole, and seed the same stretch of
// the four rows beside them (y ± 1, z ± 1); the free voxels never reached are the closed voids. This visits
// each run rather than each voxel, and needs a bit per voxel of the box.
#pragma once

#include <openvdb/openvdb.h>

namespace beadtwin::sim {

// Sets every closed void voxel of `box` in `fill` to 1 (active).
// `fill`: fill fractions (0..1); a voxel is solid when its value is at least `solid_fill`, otherwise free
// (inactive voxels read the background, which should be below it). `box`: the region flooded, in voxel
// indices; its sides (x and y at both ends, z at the top) are open to the outside, and so is its bottom row
// when `open_bottom` (else the bottom is closed, as by a build plate). For the result to mean anything the
// box holds the solid with a free voxel to spare on each open side. Memory: two bits per voxel of the box.
void fill_closed_voids(openvdb::FloatGrid& fill, const openvdb::CoordBBox& box, bool open_bottom,
                       double solid_fill);

}  // namespace beadtwin::sim
