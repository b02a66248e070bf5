// Part meshes: triangle soups read from STL (binary and ASCII) or made from built-in primitives.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace beadtwin::slicer {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;      // mm, machine frame
  std::vector<std::array<int, 3>> triangles;  // counter-clockwise seen from outside

  Eigen::Vector3d min_corner() const;
  Eigen::Vector3d max_corner() const;
  // Enclosed volume (divergence theorem); meaningful for a closed, consistently oriented mesh.
  double volume_mm3() const;
};

// Reads a binary or ASCII STL. `unit_scale` converts the file's units to mm (1 for mm, 25.4 for inches).
// Throws InputError naming the file (and the line, for ASCII) on anything that is not a usable STL.
TriangleMesh read_stl(const std::filesystem::path& path, double unit_scale = 1.0);

// Writes a binary STL (used by tests and to hand generated parts to other slicers).
void write_stl(const TriangleMesh& mesh, const std::filesystem::path& path);

// A closed box [0,size] with its minimum corner at `origin`.
TriangleMesh make_box(const Eigen::Vector3d& size, const Eigen::Vector3d& origin = Eigen::Vector3d::Zero());

// An open-top box: outer size, wall thickness and floor thickness (all mm), minimum corner at `origin`.
// A closed, watertight solid (the walls' inner faces and the floor's top face bound the cavity).
TriangleMesh make_open_box(const Eigen::Vector3d& size, double wall_mm, double floor_mm,
                           const Eigen::Vector3d& origin = Eigen::Vector3d::Zero());

}  // namespace beadtwin::slicer
