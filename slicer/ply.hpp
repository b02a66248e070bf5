// PLY meshes (the Stanford polygon file format), read by beadtwin itself.
//
// A PLY file is a text header ("ply", a format line, then element and property lines, then "end_header")
// followed by the elements' data in the order the header names them, as text (one element to a line) or as
// packed binary numbers of either byte order. beadtwin reads the "vertex" element's x, y and z and the
// "face" element's list of vertex indices ("vertex_indices" or "vertex_index"), and steps over the rest.
//
// Why not assimp, which reads the other formats: assimp 5.2 (Debian 12) believes a PLY's counts before it
// reads the data. A list that claims four billion entries makes it allocate 32 GB (the out-of-memory killer,
// not a message), a header that does not end makes it read for ever, and a face of no corners aborts the
// program (tests/fuzz finds each). Here every count is checked against the bytes that follow it, and
// every fault is a message with its line (text) or byte offset (binary).
#pragma once

#include <string>
#include <string_view>

#include "slicer/mesh.hpp"

namespace beadtwin::slicer {

// What read_ply read.
struct PlyMesh {
  TriangleMesh mesh;      // one body, unnamed; polygons cut into triangles; coordinates scaled
  int ignored_faces = 0;  // faces of fewer than three corners (points and lines bound no solid)
};

// Reads the PLY file `file`, whose bytes are `data`, scaling coordinates by `scale` (file units to mm).
// Throws InputError naming the file and the line (or byte) for a header that is not PLY, a count the data
// does not hold, a number that cannot be read, a face that refers to a vertex the file does not have, or a
// coordinate that is not finite.
PlyMesh read_ply(const std::string& file, std::string_view data, double scale);

}  // namespace beadtwin::slicer
