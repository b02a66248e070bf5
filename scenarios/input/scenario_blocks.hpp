// Readers of a scenario's blocks, internal to the scenario input library. Each reads its block through the
// block's declarations (scenarios/input/params.hpp, slicer/section_params.hpp), then checks what no single
// declaration can state (keys that depend on one another) and refuses keys nobody declared.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "scenarios/input/scenario.hpp"
#include "scenarios/input/yaml_reader.hpp"

namespace beadtwin::scenarios {

// Meshes read while loading, shared by the variants that use the same file at the same scale, with the
// repairs their reading reported.
struct MeshCache {
  std::map<std::pair<std::string, double>, std::shared_ptr<const slicer::TriangleMesh>> meshes;
  std::vector<std::string> warnings;

  std::shared_ptr<const slicer::TriangleMesh> get(const std::filesystem::path& path, double scale,
                                                  double memory_budget_bytes);
};

Machine read_machine(BlockReader& r);
Material read_material(BlockReader& r);
OutputSpec read_output(BlockReader& r);
ThermalSpec read_thermal(BlockReader& r);
RenderSpec read_render(BlockReader& r);

// The part: a mesh file (`dir` is the scenario's folder; read against the memory budget, bytes), a box or an
// open-top box; a primitive is made into its mesh here too, so every part has one (`loaded`).
PartSpec read_part(BlockReader& r, const std::filesystem::path& dir, MeshCache& meshes,
                   double memory_budget_bytes);

// The `tools:` map (patent (48)), read with `source`'s file and units; each tool prints `material`.
std::map<std::string, Tool> read_tools(const YAML::Node& node, const std::shared_ptr<YamlSource>& source,
                                       const std::map<std::string, SourceLocation>* overridden,
                                       const Material& material);

// What a section's values are found from when the section leaves them out: the machine's extruder (the print
// speed matched to its output) and motion, the material's density, the part (its bodies, `z: part`) and the
// named tools.
struct SectionContext {
  const Machine& machine;
  const Material& material;
  const slicer::TriangleMesh& part;
  const std::map<std::string, Tool>& tools;
};
slicer::SectionParams read_section(BlockReader& r, const SectionContext& context);

// A list of gates from `file` (a scenario's `gates:`, or a gates file).
std::vector<Gate> read_gates(const YAML::Node& list, const std::string& file);

}  // namespace beadtwin::scenarios
