// The as-printed skin: the deposit's outer surface as a triangle mesh, for programs that open meshes
// (Blender, MeshLab, a CAD package comparing it with the part) rather than volumes.
//
// The skin is the iso-surface fill = 0.5 of the deposit's fill grid (a fog volume: 1 in full voxels, 0
// outside), meshed by OpenVDB's tools::volumeToMesh. Adaptivity merges the small faces of flat regions into
// larger ones; ridges between beads and corners keep their detail. The triangles face outwards: seen from
// outside, their corners run counter-clockwise (the right-hand rule gives the outward normal), as STL and PLY
// readers expect, so the mesh's signed volume is the volume it encloses.
//
// The skin grows with the part's surface, a bead-by-bead model of the same print (every move a swept tube)
// with the number of moves: bead_by_bead_stl() gives that model's size for the report to compare with.
// Measured in triangles at the default 0.3 mm tolerance and adaptivity 0: the bead model holds 8.8 times the
// skin's on the default box (flat faces), 3.4 times on the LSAM hull-mould shell, whose flared wall shows a
// ledge at every layer (docs/PERFORMANCE.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string_view>
#include <vector>

#include <openvdb/openvdb.h>

#include "core/toolpath.hpp"
#include "sim/deposit.hpp"

namespace beadtwin::sim {

// A triangle mesh of the skin, mm.
struct SkinMesh {
  std::vector<openvdb::Vec3s> points_mm;  // machine frame; every point is used by a triangle
  std::vector<openvdb::Vec3I> triangles;  // indices into points_mm, counter-clockwise seen from outside
};

// The deposit's iso-surface fill = 0.5 as OpenVDB's mesher (tools::volumeToMesh) gives it: polygons wound
// clockwise seen from outside, quads where it can. The skin and the pictures are both made from it.
struct FillSurface {
  std::vector<openvdb::Vec3s> points_mm;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
};

// Meshes `deposit`'s fill grid at `adaptivity` (as extract_skin below). Empty for a deposit without
// material. Throws std::invalid_argument for an adaptivity outside [0, 1].
FillSurface mesh_fill(const Deposit& deposit, double adaptivity);

// Meshes the skin of `deposit`. `adaptivity` in [0, 1]: 0 keeps about one quad (two triangles) per voxel face
// crossed by the surface; larger values merge faces where the surface is flat. A deposit without material
// has no skin: the mesh is empty. With `outer_only`, the closed shells around voids inside the part (pieces
// of the mesh facing inwards, negative signed volume) are left out: the outer skin. With `tolerance_mm` > 0
// the mesh is then simplified by edge collapse (meshoptimizer's quadric simplifier) as long as the surface
// moves less than that. The unsimplified mesh is closed and manifold; the simplified one is closed (every
// edge met as often one way as the other) and its folds are dropped, but where two sheets of the surface
// close up an edge may be shared by four triangles and a triangle may have no area (rare: about one in a
// thousand, docs/PERFORMANCE.md). Throws std::invalid_argument for an adaptivity outside [0, 1].
SkinMesh extract_skin(const Deposit& deposit, double adaptivity, bool outer_only = true,
                      double tolerance_mm = 0.0);
// The same from the fill grid's surface already meshed (mesh_fill).
SkinMesh extract_skin(const FillSurface& surface, bool outer_only = true, double tolerance_mm = 0.0);

// The volume the mesh encloses, mm³: positive when its triangles face outwards.
double enclosed_volume_mm3(const SkinMesh& mesh);

enum class MeshFormat { kPly, kStl };
constexpr MeshFormat kMeshFormats[] = {MeshFormat::kPly, MeshFormat::kStl};
// "ply" or "stl", also the file extension.
std::string_view to_string(MeshFormat format);

// Writes `mesh` atomically as binary PLY (little-endian float vertices, uint32 triangle indices) or binary
// STL (80-byte header, facet normals). Lengths in mm. Throws std::invalid_argument for an empty mesh (a file
// without triangles helps nobody) and std::runtime_error when the file cannot be written, both naming `path`;
// nothing is left at `path` then.
void write_mesh(const SkinMesh& mesh, const std::filesystem::path& path, MeshFormat format);

// The size a binary STL would have that models the print bead by bead. Assumptions: every depositing move
// (Move::deposits) is one tube of `facets_around` flat sides around its section (2 triangles each) closed by
// two flat end caps (a fan of facets_around - 2 triangles each), so 4 · facets_around - 4 triangles per move;
// 50 bytes per triangle and an 84-byte header, as binary STL stores them. Nothing is shared between moves.
// What bead_by_bead_stl estimates.
struct BeadStlEstimate {
  std::size_t moves = 0;
  std::size_t triangles = 0;
  std::uintmax_t bytes = 0;
};
BeadStlEstimate bead_by_bead_stl(const Toolpath& toolpath, int facets_around = 16);

}  // namespace beadtwin::sim
