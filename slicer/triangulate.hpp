// Cutting a mesh file's polygons into triangles.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

namespace beadtwin::slicer {

// Triangles covering the planar polygon `corners` (indices into the result are positions in `corners`), by
// ear clipping in the polygon's own plane, so concave polygons (an L-shaped face of a CAD export) are cut
// inside their outline. A polygon that has no area, or that crosses itself so that no ear is left, is cut as
// a fan from its first corner for what remains: repair drops what is degenerate. Ear clipping takes up to
// n³ steps, so a polygon of more than 256 corners (no CAD export writes one; a fuzzer does) is cut as a fan.
//
// Polygons are cut here rather than by assimp's aiProcess_Triangulate, which asserts (aborting the program,
// in Debian's build of assimp 5.2) on a face with no corners, as a PLY may hold (found by tests/fuzz).
std::vector<std::array<int, 3>> triangulate_polygon(const std::vector<Eigen::Vector3d>& corners);

}  // namespace beadtwin::slicer
