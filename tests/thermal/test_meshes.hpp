// Hand-built thermal meshes shared by the heat tests (tests/thermal/heat_test.cpp, and the solve across MPI
// ranks in tests/thermal/mpi/): a ThermalMesh is a plain struct, so each test checks the solver alone, with
// cells of known capacity, links of known area and distance, and open and table area where the problem has
// its boundaries.
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>

#include "core/material.hpp"
#include "thermal/heat.hpp"
#include "thermal/mesh.hpp"

namespace beadtwin::thermal {

// The reference material of docs/physics.md (20 % CF-ABS), orthotropic, with radiation off: the analytic
// solutions below are linear.
inline Material test_material() {
  Material m;
  m.density_kg_m3 = 1140.0;
  m.specific_heat_J_kgK = 1640.0;
  m.conductivity_along_W_mK = 0.59;
  m.conductivity_across_W_mK = 0.48;
  m.conductivity_through_W_mK = 0.35;
  m.emissivity = 0.0;
  m.deposition_temp_c = 200.0;
  return m;
}

inline ThermalCell cell_at(const Eigen::Vector3d& centroid_mm, double volume_mm3, double birth_s = 0.0,
                           int layer = 0) {
  ThermalCell c;
  c.centroid_mm = centroid_mm;
  c.volume_mm3 = volume_mm3;
  c.birth_s = birth_s;
  c.layer = layer;
  return c;
}

// A planar contact from cell a to cell b: `area_vector_mm2` from a towards b.
inline ThermalLink link(std::uint32_t a, std::uint32_t b, const Eigen::Vector3d& area_vector_mm2,
                        bool interface = false) {
  ThermalLink l;
  l.a = a;
  l.b = b;
  l.area_vector_mm2 = area_vector_mm2;
  l.faces_mm2 = area_vector_mm2.norm();
  l.interface = interface;
  return l;
}

// A block of nx × ny × layers cells of 5 × 5 × 4 mm on a table, each layer laid row by row over ny s and the
// next begun 60 s after it; open to the air on its sides and top. The links between layers are interfaces.
inline ThermalMesh block(int nx, int ny, int layers) {
  constexpr double kSide = 5.0, kHeight = 4.0;
  ThermalMesh mesh;
  mesh.voxel_size_mm = 1.0;
  const auto index = [nx, ny](int x, int y, int z) {
    return static_cast<std::uint32_t>((z * ny + y) * nx + x);
  };
  for (int z = 0; z < layers; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        ThermalCell c = cell_at({(x + 0.5) * kSide, (y + 0.5) * kSide, (z + 0.5) * kHeight},
                                kSide * kSide * kHeight, z * 60.0 + y, z);
        c.open_area_mm2 = (x == 0 || x == nx - 1 ? kSide * kHeight : 0.0) +
                          (y == 0 || y == ny - 1 ? kSide * kHeight : 0.0) +
                          (z == layers - 1 ? kSide * kSide : 0.0);
        if (z == 0) c.table_area_mm2 = kSide * kSide;
        mesh.cells.push_back(c);
      }
  for (int z = 0; z < layers; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        if (x + 1 < nx)
          mesh.links.push_back(link(index(x, y, z), index(x + 1, y, z), {kSide * kHeight, 0, 0}));
        if (y + 1 < ny)
          mesh.links.push_back(link(index(x, y, z), index(x, y + 1, z), {0, kSide * kHeight, 0}));
        if (z + 1 < layers)
          mesh.links.push_back(link(index(x, y, z), index(x, y, z + 1), {0, 0, kSide * kSide}, true));
      }
  return mesh;
}

// A thin wall of one bead per layer, 40 layers of 40 cells (1 mm pieces of a 0.5 x 0.2 mm bead), each layer
// laid over 8 s and the next begun 20 s after it, on a heated table: a small desktop print, long enough that
// its lower layers settle (docs/physics.md, settled cells). Lumped, those layers become a few cells each; the
// answer must be the unlumped one's within what the solver's tolerance moves it.
inline ThermalMesh thin_wall() {
  constexpr int kAlong = 40, kLayers = 40;
  constexpr double kLength = 1.0, kWidth = 0.5, kHeight = 0.2;
  ThermalMesh mesh;
  mesh.voxel_size_mm = 0.1;
  for (int z = 0; z < kLayers; ++z)
    for (int x = 0; x < kAlong; ++x) {
      ThermalCell c = cell_at({(x + 0.5) * kLength, 0.0, (z + 0.5) * kHeight}, kLength * kWidth * kHeight,
                              z * 20.0 + x * 0.2, z);
      c.open_area_mm2 = 2.0 * kLength * kHeight + (x == 0 || x == kAlong - 1 ? kWidth * kHeight : 0.0) +
                        (z == kLayers - 1 ? kLength * kWidth : 0.0);
      if (z == 0) c.table_area_mm2 = kLength * kWidth;
      mesh.cells.push_back(c);
    }
  const auto index = [&](int x, int z) { return static_cast<std::uint32_t>(z * kAlong + x); };
  for (int z = 0; z < kLayers; ++z)
    for (int x = 0; x < kAlong; ++x) {
      if (x + 1 < kAlong) mesh.links.push_back(link(index(x, z), index(x + 1, z), {kWidth * kHeight, 0, 0}));
      if (z + 1 < kLayers)
        mesh.links.push_back(link(index(x, z), index(x, z + 1), {0, 0, kLength * kWidth}, true));
    }
  std::sort(mesh.links.begin(), mesh.links.end(), [](const ThermalLink& p, const ThermalLink& q) {
    return std::pair(p.a, p.b) < std::pair(q.a, q.b);
  });
  return mesh;
}

// How the thin wall is printed and cooled: deposited at 240 °C, radiating, on a table at 100 °C, cooled for
// 120 s after the last bead, settled cells looked for every two layers (the default waits for 4,096 cells).
struct HeatCase {
  Material material;
  Environment env;
  HeatOptions options;
};
inline HeatCase thin_wall_print() {
  HeatCase c;
  c.material = test_material();
  c.material.emissivity = 0.9;
  c.material.deposition_temp_c = 240.0;
  c.env.bed_temp_c = 100.0;
  c.options.cooldown_s = 120.0;
  c.options.lump_check_cells = 80;
  return c;
}

// How the block is printed and cooled: radiating (so the right-hand side is nonlinear), on a table at 80 °C,
// cooled for 300 s after the last layer.
inline HeatCase block_print() {
  HeatCase c;
  c.material = test_material();
  c.material.emissivity = 0.9;
  c.env.bed_temp_c = 80.0;
  c.options.cooldown_s = 300.0;
  return c;
}

}  // namespace beadtwin::thermal
