// Cutting a mesh with a horizontal plane into the region it occupies at that height.
#pragma once

#include "slicer/mesh.hpp"
#include "slicer/polygons.hpp"

namespace beadtwin::slicer {

struct SliceStats {
  int open_chains = 0;  // loops that did not close (holes in the mesh); closed by a straight segment
};

// The region of the mesh's solid at height z (mm): outer contours CCW, holes CW. The plane never touches
// a vertex exactly (vertices on the plane count as above it), so results are stable at layer boundaries.
Polygons slice_mesh(const TriangleMesh& mesh, double z_mm, SliceStats* stats = nullptr);

}  // namespace beadtwin::slicer
