// The beads' contact through the layers as the thermal mesh holds it, at a voxel size: per layer, the
// cells' volume, the area they share with the layer above (contacts within about 37° of horizontal), the
// volume over that area (a bead's height where the contact is as wide as the bead, more where its rounded
// sides narrow it) and the height of the layer's centroid against the toolpath's (docs/validation.md, mesh
// convergence: why the verdicts move with the voxel size).
//
//   layer_contact SCENARIO [VOXEL_MM [--no-follow]]   (the scenario's first variant; VOXEL_MM 0 or none: its
//   own; --no-follow: every bead at its nominal height, DepositOptions::follow_substrate false)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <map>
#include <string_view>

#include "scenarios/input/scenario.hpp"
#include "scenarios/variant_stages.hpp"
#include "sim/deposit.hpp"
#include "thermal/mesh.hpp"

using namespace beadtwin;

int main(int argc, char** argv) {
  const bool no_follow = argc == 4 && std::string_view(argv[3]) == "--no-follow";
  if (argc < 2 || argc > 4 || (argc == 4 && !no_follow)) {
    std::fprintf(stderr, "usage: layer_contact SCENARIO [VOXEL_MM [--no-follow]]\n");
    return 2;
  }
  try {
    const scenarios::Scenario sc = scenarios::load_scenario(argv[1]);
    const scenarios::Variant& v = sc.variants.front();
    const Toolpath tp = scenarios::variant_toolpath(v);
    sim::DepositOptions o = scenarios::deposit_options(v);
    if (argc >= 3 && std::atof(argv[2]) > 0.0) o.voxel_size_mm = std::atof(argv[2]);
    o.follow_substrate = !no_follow;
    const sim::Deposit d = sim::deposit(tp, o);
    const thermal::ThermalMesh mesh = thermal::build_thermal_mesh(tp, d, scenarios::thermal_mesh_options(v));
    struct Layer {
      double volume = 0.0, moment_z = 0.0, up = 0.0;
    };
    std::map<int, Layer> layers;
    for (const thermal::ThermalCell& c : mesh.cells) {
      layers[c.layer].volume += c.volume_mm3;
      layers[c.layer].moment_z += c.volume_mm3 * c.centroid_mm.z();
    }
    for (const thermal::ThermalLink& l : mesh.links) {
      const int a = mesh.cells[l.a].layer, b = mesh.cells[l.b].layer;
      const double area = l.area_vector_mm2.norm();
      if (a != b && area > 0.0 && std::abs(l.area_vector_mm2.z()) > 0.8 * area)
        layers[std::min(a, b)].up += area;
    }
    std::printf("voxel %.3f mm, %zu cells, %zu layers\n", d.voxel_size_mm, mesh.cells.size(),
                tp.layers.size());
    std::printf("layer  height mm  volume mm3  contact up mm2  volume/contact mm  centroid - toolpath mm\n");
    for (const auto& [index, layer] : layers) {
      if (index < 0 || static_cast<std::size_t>(index) + 1 >= tp.layers.size() || layer.up <= 0.0) continue;
      const ToolpathLayer& t = tp.layers[static_cast<std::size_t>(index)];
      std::printf("%5d %10.2f %11.0f %15.0f %18.2f %22.2f\n", index, t.height_mm, layer.volume, layer.up,
                  layer.volume / layer.up, layer.moment_z / layer.volume - (t.z_mm - 0.5 * t.height_mm));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "layer_contact: %s\n", e.what());
    return 2;
  }
  return 0;
}
