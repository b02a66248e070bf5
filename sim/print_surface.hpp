// The printed part as the comparison with the CAD measures it (sim/cad_compare.hpp): which voxels are the
// print, where the build plate is, the print made solid where its voids are porosity rather than surface,
// and that solid's surface for distance queries.
//
// The build plate: the table, not the print, forms the faces that stand on it. The print's bottom is no
// surface to measure from: the table stands in for material below it (the lowest printed row copied down
// through the plate), so the stock of a side face does not fall to nothing at its foot, however much
// material stands beside it; the sides carry straight on down, as the first row shaped them.
#pragma once

#include <openvdb/openvdb.h>

#include "sim/nearest_triangles.hpp"

namespace beadtwin::sim {

// The printed part: voxels at least half full (as the renderer draws it, and as the skin is meshed).
constexpr double kPrintedFill = 0.5;

// The lowest row (voxel index k) of printed voxels of `fill` (fill fractions): the plate is at its bottom.
// Throws InputError when no voxel is printed.
int plate_row(const openvdb::FloatGrid& fill);

// The print as its surface is measured, a new grid: `fill` (fill fractions) with the inside of its slits
// one voxel thin filled (sim/slits.hpp) and its closed voids filled (sim/closed_voids.hpp), within its
// bounding box grown by a voxel. With `on_plate`, the box's bottom is `plate_k` (plate_row), which the table
// closes, and every voxel of that row is copied `depth` voxels down (≥ 0) through the plate; without it the
// bottom is open like the other sides and nothing is added below.
openvdb::FloatGrid::Ptr solid_print(const openvdb::FloatGrid& fill, int plate_k, bool on_plate, int depth);

// The surface of `solid` (fill fractions, as solid_print gives it) for the distance from a point to it: its
// isosurface at kPrintedFill, the surface the renderer draws, meshed as the skin is (sim/skin.hpp, every
// shell kept; flat stretches merged into larger polygons where the normals agree within about 1 %: a bead's
// flank is a row of identical voxel faces), its triangles facing out, so that
// NearestTriangles::Distance::outside holds. Triangles without area are left out: they have no side to tell
// inside from outside by.
NearestTriangles print_surface(const openvdb::FloatGrid::Ptr& solid);

}  // namespace beadtwin::sim
