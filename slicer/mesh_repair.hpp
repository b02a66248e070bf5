// Repairing the triangle soups that real-world mesh files hold, so slicing sees closed, consistently
// oriented shells where the file allows it, and the user learns what was wrong.
#pragma once

#include <string>

#include "slicer/mesh.hpp"

namespace beadtwin::slicer {

// The weld tolerance as a fraction of the bounding-box diagonal.
inline constexpr double kWeldToleranceOfDiagonal = 1e-6;

// Repairs `raw` body by body (a body's vertices are never shared with another body):
//  - welds corners at the same point, and points closer than kWeldToleranceOfDiagonal times the bounding-box
//    diagonal (counted in welded_vertices);
//  - drops faces with two corners at one vertex (degenerate_faces); zero-area faces with three distinct
//    corners stay, as they keep the edges of their neighbours connected;
//  - drops repeated faces: one copy is kept when all copies wind the same way, none when the windings are
//    opposite (an internal sheet) (duplicate_faces);
//  - makes the winding consistent over each shell (faces connected across edges shared by exactly two
//    faces), flipping the minority (flipped_faces);
//  - orients each closed shell outward (positive volume), or inward when it lies inside an odd number of
//    the body's other closed shells: a cavity (reversed_shells, cavities). Open shells keep their majority
//    winding.
// Counts open and non-manifold edges, shells and bodies. Bodies left without triangles are dropped and the
// others renumbered. Preconditions: raw.body parallel to raw.triangles (or empty: one body), indices in
// range, coordinates finite. Sets the counts of `report` (not its warnings).
TriangleMesh repair_mesh(const TriangleMesh& raw, MeshReport& report);

// Appends to report.warnings one line per nonzero count, each starting with "source: ".
void add_repair_warnings(MeshReport& report, const std::string& source);

}  // namespace beadtwin::slicer
