// Part meshes: read from STL, OBJ, 3MF, AMF (through assimp) or PLY (slicer/ply.hpp) and repaired, or made
// from built-in primitives. A part may hold several bodies (the outside shape plus interior structures),
// each a set of triangles tagged with its body index.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "core/enum_names.hpp"
#include "core/memory.hpp"

namespace beadtwin::slicer {

// A part as triangles, each tagged with its body.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;      // mm, machine frame
  std::vector<std::array<int, 3>> triangles;  // counter-clockwise seen from outside
  // Per triangle: index into body_names (parallel to triangles). A mesh built by hand may leave both
  // empty: then it is one body.
  std::vector<int> body;
  std::vector<std::string> body_names;  // one per body, unique

  Eigen::Vector3d min_corner() const;  // of the bounding box, mm
  Eigen::Vector3d max_corner() const;
  // Enclosed volume (divergence theorem); meaningful for a closed, consistently oriented mesh.
  double volume_mm3() const;
};

// What read_mesh found wrong with a file and repaired (or could not). All counts are after welding.
struct MeshReport {
  int welded_vertices = 0;     // distinct vertices closer than the weld tolerance to another, merged into it
  int degenerate_faces = 0;    // faces with two corners at one (welded) vertex, dropped
  int duplicate_faces = 0;     // repeated faces dropped (both copies when their windings are opposite)
  int flipped_faces = 0;       // faces turned to match the winding of their neighbours
  int reversed_shells = 0;     // closed shells turned inside out as a whole (to face out, or in for cavities)
  int cavities = 0;            // closed shells inside another shell of the same body, oriented as holes
  int open_edges = 0;          // edges with one face: the mesh has holes there (slices close them straight)
  int non_manifold_edges = 0;  // edges shared by more than two faces
  int ignored_primitives = 0;  // points and lines in the file, which bound no solid
  int shells = 0;              // connected pieces (across edges shared by exactly two faces)
  int bodies = 0;              // bodies after repair (the file's separate meshes or objects)
  double weld_tolerance_mm = 0.0;
  std::vector<std::string> warnings;  // one line per kind of problem, "file: what, how many", for the user
};

// The largest part, mm (100 m): anything larger, a mesh or a section's outline, is taken as a mistake of
// units.
inline constexpr double kMaxPartSizeMm = 100'000.0;

// Reads a part mesh in any format assimp knows (STL binary and ASCII, OBJ, 3MF, AMF, ...) or PLY, bakes the
// file's node transforms, scales by `unit_scale` (file units to mm: 1 for mm, 25.4 for inches) and repairs
// it: welds vertices within 1e-6 of the bounding-box diagonal, drops degenerate and duplicate faces, makes
// the winding consistent over each connected shell and orients closed shells outward (inward for a shell
// nested inside another shell of the same body: a cavity). Each of the file's meshes/objects is a body,
// named after its node or mesh (or the file's stem). Fills `report`, when given, with what was repaired.
// Throws InputError naming the file when it cannot be read (with assimp's message), has a coordinate that
// is not finite, is larger than 100 m, or has no triangles left after repair; and, before reading it, when
// reading it would take more memory than `memory_budget_bytes` (core/memory.hpp; 0: three quarters of the
// machine's), as read_mesh_cost estimates it.
TriangleMesh read_mesh(const std::filesystem::path& path, double unit_scale = 1.0,
                       MeshReport* report = nullptr, double memory_budget_bytes = 0.0);

// The memory reading the mesh file `path` of `file_bytes` bytes takes, bytes, from its name and `head`, its
// first bytes (binary STL's triangle count is in its first 84): 300 bytes a triangle for binary STL, else 24
// bytes a byte of file. All of it is fixed: a mesh has no voxels.
MemoryCost read_mesh_cost(const std::filesystem::path& path, std::uintmax_t file_bytes,
                          const std::string& head);

// Writes a binary STL of all bodies (used by tests and to hand generated parts to other slicers).
void write_stl(const TriangleMesh& mesh, const std::filesystem::path& path);

// The triangles of one body (0 <= body < body_names.size(), or body 0 of a mesh without body tags) as a mesh
// of its own with that one body.
TriangleMesh select_body(const TriangleMesh& mesh, int body);

// Slice plane (patent (44)): which of the part's planes its layers lie in. kTop slices the part as modelled
// (layers parallel to XY); kFront lays it down so layers are parallel to its XZ plane (the part's +Y
// becomes up), kSide so they are parallel to its YZ plane (+X becomes up).
enum class SlicePlane : std::uint8_t { kTop, kFront, kSide };
inline constexpr EnumName<SlicePlane> kSlicePlaneNames[] = {
    {SlicePlane::kTop, "top"}, {SlicePlane::kFront, "front"}, {SlicePlane::kSide, "side"}};
constexpr std::span<const EnumName<SlicePlane>> enum_names(SlicePlane) {
  return kSlicePlaneNames;
}
// The plane's name in scenarios and reports: top, front or side.
inline std::string_view to_string(SlicePlane plane) {
  return name_of(plane);
}
// The part turned (a proper rotation: the faces keep their outward winding) so `plane` lies horizontal,
// and moved so its bounding box keeps its minimum corner.
TriangleMesh lay_down(const TriangleMesh& mesh, SlicePlane plane);

// The index of the body named `name`, or -1 when there is none.
int find_body(const TriangleMesh& mesh, std::string_view name);
// The body names, comma-separated, for messages ("part" for a mesh of one unnamed body).
std::string body_list(const TriangleMesh& mesh);

// A closed box [0,size] with its minimum corner at `origin`; one body named "part".
TriangleMesh make_box(const Eigen::Vector3d& size, const Eigen::Vector3d& origin = Eigen::Vector3d::Zero());

// One tier of an open box's wall: the wall is `wall_mm` thick up to `z_top_mm` above the box's bottom.
struct WallTier {
  double z_top_mm = 0.0;
  double wall_mm = 0.0;
};

// An open-top box whose wall thickness changes in tiers from the floor up (the last tier reaches the top,
// whatever its z_top_mm). Walls thin on the inside: a thinner tier stands on a ledge of the one below.
// Preconditions: tiers not empty, z_top_mm increasing, every wall less than half the smaller side.
TriangleMesh make_open_box(const Eigen::Vector3d& size, const std::vector<WallTier>& tiers, double floor_mm,
                           const Eigen::Vector3d& origin = Eigen::Vector3d::Zero());

// An open-top box: outer size, wall thickness and floor thickness (all mm), minimum corner at `origin`.
// A closed, watertight solid (the walls' inner faces and the floor's top face bound the cavity); one body
// named "part" (as every open box).
TriangleMesh make_open_box(const Eigen::Vector3d& size, double wall_mm, double floor_mm,
                           const Eigen::Vector3d& origin = Eigen::Vector3d::Zero());

}  // namespace beadtwin::slicer
