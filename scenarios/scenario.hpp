// Scenarios: a part, a machine, a material, sections with their print parameters, variants that
// override parameters, and gates. Loading validates everything before any heavy work starts and reports
// problems with file, line, column and key.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/flow.hpp"
#include "core/material.hpp"
#include "core/toolpath.hpp"
#include "slicer/gcode_writer.hpp"
#include "slicer/mesh.hpp"
#include "slicer/plan.hpp"

namespace beadtwin::scenarios {

struct Machine {
  std::string name;
  std::string description;
  std::string kind;
  MotionLimits motion;
  double extruder_output_kg_s = 0.0;
  double extruder_max_output_kg_s = 0.0;
  Extruder extruder;  // its max flow is set from max_output once the material's density is known
  Environment environment;
  slicer::GcodeDialect dialect;
};

struct PartSpec {
  enum class Kind { kNone, kMesh, kBox, kOpenBox };
  Kind kind = Kind::kOpenBox;
  std::filesystem::path mesh;                          // kMesh: resolved path
  double mesh_scale = 1.0;                             // mesh file units to mm
  std::shared_ptr<const slicer::TriangleMesh> loaded;  // the part as a mesh, made or read once when loading
  Eigen::Vector3d size = Eigen::Vector3d::Zero();      // kBox, kOpenBox: outer size, mm
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();    // minimum corner, mm
  std::vector<slicer::WallTier> tiers;                 // kOpenBox: wall thickness from the floor up
  double floor_mm = 0.0;                               // kOpenBox
  std::string describe() const;
};

struct OutputSpec {
  double voxel_size_mm = 0.0;
  SourceLocation voxel_size_at;  // where it was set, for messages found when depositing
  int image_width = 1280;
  int image_height = 800;
};

struct ThermalSpec {
  int nodes_per_layer = 2;
  double cooldown_s = 600.0;
  double rel_tol = 1e-6;
  double abs_tol_k = 1e-4;
};

// One parameter set, fully resolved: what a run needs, nothing more.
struct Variant {
  std::string name;
  std::map<std::string, std::string> overrides;  // key path -> value text, as the variant set them
  Machine machine;
  Material material;
  PartSpec part;
  std::vector<slicer::SectionParams> sections;
  OutputSpec output;
  ThermalSpec thermal;
};

enum class GateOp { kLess, kLessEqual, kGreater, kGreaterEqual, kEqual, kNotEqual };

struct Gate {
  std::string expr;    // as written
  std::string metric;  // dotted metric path ("interfaces.too_cold_fraction")
  GateOp op = GateOp::kLess;
  double threshold = 0.0;
  SourceLocation where;
};

struct Scenario {
  std::string name;
  std::string description;
  std::string file;  // where it was read from ("<built-in default>" for the embedded one)
  std::vector<Variant> variants;
  std::vector<Gate> gates;
  std::vector<std::string>
      warnings;  // things repaired or doubtful in the inputs (mesh repairs), for the user
};

// Loads and validates a scenario file. Machine and material given by name are looked up as
// <scenario dir>/machines/NAME.yaml (materials/NAME.yaml), then among the files shipped with beadtwin.
Scenario load_scenario(const std::filesystem::path& path);
// Loads scenario text (for the embedded default and for tests); `file` is used in messages and to resolve
// relative paths (may be empty).
Scenario load_scenario_text(const std::string& text, const std::string& file);
// The built-in default scenario (embedded in the binary).
Scenario load_default_scenario();

// Metric names a gate may use (the report's metrics).
const std::vector<std::string>& gate_metrics();

}  // namespace beadtwin::scenarios
