#include "scenarios/input/scenario_blocks.hpp"

#include <cmath>
#include <limits>
#include <string_view>

#include <fmt/format.h>

#include "scenarios/input/params.hpp"
#include "scenarios/input/ranges.hpp"

namespace beadtwin::scenarios {

std::string PartSpec::describe() const {
  switch (kind) {
    case Kind::kNone:
      return "none (AM Outline sections only)";
    case Kind::kMesh:
      return mesh.filename().string();
    case Kind::kBox:
      return fmt::format("box {:.0f} x {:.0f} x {:.0f} mm", size.x(), size.y(), size.z());
    case Kind::kOpenBox: {
      std::string walls;
      for (const auto& t : tiers) walls += fmt::format("{}{:.0f}", walls.empty() ? "" : "/", t.wall_mm);
      return fmt::format("open-top box {:.0f} x {:.0f} x {:.0f} mm, wall{} {} mm, floor {:.0f} mm", size.x(),
                         size.y(), size.z(), tiers.size() > 1 ? "s" : "", walls, floor_mm);
    }
  }
  return "?";
}

std::shared_ptr<const slicer::TriangleMesh> MeshCache::get(const std::filesystem::path& path, double scale,
                                                           double memory_budget_bytes) {
  auto& slot = meshes[{path.string(), scale}];
  if (!slot) {
    slicer::MeshReport report;
    slot = std::make_shared<const slicer::TriangleMesh>(
        slicer::read_mesh(path, scale, &report, memory_budget_bytes));
    warnings.insert(warnings.end(), report.warnings.begin(), report.warnings.end());
  }
  return slot;
}

namespace {

// The extruder's and the program's settings that only make sense together.
void check_extruder(BlockReader& r, const Machine& m) {
  if (m.extruder.kind == ExtruderKind::kFilament && !(m.extruder.filament_diameter_mm > 0))
    r.fail(r.take("extruder.filament_diameter"), "extruder.filament_diameter",
           "a filament extruder needs its filament diameter");
  if (m.extruder.has_constant_feed() && m.extruder.kind != ExtruderKind::kFilament)
    r.fail(r.take("extruder.constant_feed"), "extruder.constant_feed",
           "a constant feed is a filament drive's: set extruder.kind to filament, or give a pump its speed "
           "words");
  if (m.extruder_output_kg_s > m.extruder_max_output_kg_s)
    r.fail(r.take("extruder.output"), "extruder.output",
           "nominal output is above the extruder's maximum output");
  if (m.dialect.roller_down.empty() != m.dialect.roller_up.empty()) {
    const char* key = m.dialect.roller_down.empty() ? "gcode.roller_up" : "gcode.roller_down";
    r.fail(r.take(key), key, "give both roller codes (down and up), or neither");
  }
  if (m.extruder.has_constant_feed() && (m.dialect.melt_on.empty() || m.dialect.melt_off.empty()))
    r.fail(
        r.take("extruder.constant_feed"), "extruder.constant_feed",
        "a constant feed runs from melt on to melt off: give the machine gcode.melt_on and gcode.melt_off");
}

// The material's inputs that take a range, at their values.
std::vector<RangeKey> material_range_keys(const Material& m) {
  using D = Dimension;
  const bool table = !m.specific_heat_by_temp.empty();
  return {
      {"density", D::kDensity, m.density_kg_m3},
      {"specific_heat", D::kSpecificHeat, m.specific_heat_J_kgK, table,
       " (the material gives specific_heat_by_temp, which the factors scale)"},
      {"conductivity", D::kConductivity, m.conductivity_through_W_mK, true,
       " (the three conductivities move by one factor)"},
      {"emissivity", D::kFraction, m.emissivity},
      {"deposition_temp", D::kTemperature, m.deposition_temp_c},
      {"glass_transition", D::kTemperature, m.glass_transition_c},
      {"fusion.viscosity", D::kViscosity, m.viscosity_ref_Pa_s},
      {"fusion.max_slump", D::kFraction, m.max_slump},
      {"fusion.reptation_time", D::kTime, m.reptation_time_ref_s},
      {"fusion.wlf_c1", D::kDimensionless, m.wlf_c1},
      {"fusion.wlf_c2", D::kDimensionless, m.wlf_c2_k},
      {"fusion.activation_energy", D::kMolarEnergy, m.healing_activation_J_mol},
      {"fusion.required_healing", D::kFraction, m.required_healing},
  };
}

std::vector<RangeKey> environment_range_keys(const Environment& e) {
  using D = Dimension;
  return {
      {"environment.ambient", D::kTemperature, e.ambient_c},
      {"environment.bed_temp", D::kTemperature, e.bed_temp_c},
      // Read as factors on the value, which scale convection_by_height alike where the machine gives it.
      {"environment.convection", D::kHeatTransferCoeff, e.convection_W_m2K},
      {"environment.bed_contact", D::kHeatTransferCoeff, e.bed_contact_W_m2K},
      {"environment.fan_convection", D::kHeatTransferCoeff, e.fan_convection_W_m2K},
  };
}

}  // namespace

Machine read_machine(BlockReader& r) {
  Machine m;
  r.read(machine_params(), m);
  m.environment.ranges = read_ranges(r, environment_range_keys(m.environment));
  check_extruder(r, m);
  if (m.rapid_g0) m.dialect.rapid_feed_mm_s = m.motion.max_travel_mm_s;
  r.finish(machine_params());
  return m;
}

Material read_material(BlockReader& r) {
  Material m;
  r.read(material_params(), m);
  // The table, where the material gives one, is what the heat solve uses: a variant that sets the one value
  // alone would change nothing.
  const auto* overridden = r.overridden();
  const auto set_by_variant = [&](std::string_view key) {
    return overridden != nullptr && overridden->contains(r.full_key(key));
  };
  if (!m.specific_heat_by_temp.empty() && set_by_variant("specific_heat") &&
      !set_by_variant("specific_heat_by_temp"))
    r.fail(r.take("specific_heat"), "specific_heat",
           "this material gives specific_heat_by_temp, which the heat solve uses instead: set "
           "material.specific_heat_by_temp, or set it to null as well to use this one value");
  if (std::isnan(m.softening_temp_c)) m.softening_temp_c = m.glass_transition_c;
  m.ranges = read_ranges(r, material_range_keys(m));
  r.finish(material_params());
  return m;
}

OutputSpec read_output(BlockReader& r) {
  OutputSpec o;
  r.read(output_params(), o);
  o.voxel_size_at = r.where(r.take("voxel_size"), "voxel_size");
  r.finish(output_params());
  return o;
}

ThermalSpec read_thermal(BlockReader& r) {
  ThermalSpec t;
  r.read(thermal_params(), t);
  if (t.cells_across % 2 == 0)
    r.fail(r.take("cells_across"), "cells_across",
           fmt::format("must be odd (a centre strip and edges on both sides), got {}", t.cells_across));
  // Snapshot times, or `end` for the end of the print (infinity until the print's length is known).
  if (YAML::Node snaps = r.take("snapshots"); snaps.IsDefined()) {
    const ParamInfo& info = find_param(thermal_params(), "snapshots");
    if (!snaps.IsSequence())
      r.fail(snaps, "snapshots", "expected a list of times, such as [30 min, 1 h, end]");
    for (const YAML::Node& s : snaps) {
      if (s.IsScalar() && s.Scalar() == "end") {
        t.snapshot_times_s.push_back(std::numeric_limits<double>::infinity());
        continue;
      }
      const double value = r.parse(s, info.dim, "snapshots");
      r.check_range(info, value, s);
      t.snapshot_times_s.push_back(value);
    }
  }
  r.finish(thermal_params());
  return t;
}

namespace {

// A mesh part: the file (relative to the scenario) in its units, read once for every variant.
void read_mesh_part(BlockReader& r, PartSpec& p, const std::filesystem::path& dir, MeshCache& meshes,
                    double memory_budget_bytes) {
  p.kind = PartSpec::Kind::kMesh;
  YAML::Node node = r.take("mesh");
  if (!node.IsScalar()) r.fail(node, "mesh", "expected the path of a mesh file (STL, OBJ, 3MF, AMF or PLY)");
  p.mesh = dir / node.Scalar();
  if (!std::filesystem::exists(p.mesh))
    r.fail(node, "mesh", fmt::format("no such file: {}", p.mesh.string()));
  YAML::Node units = r.take("mesh_units");
  if (units.IsDefined()) {
    try {
      p.mesh_scale = to_internal(1.0, units.IsScalar() ? units.Scalar() : "", Dimension::kLength);
    } catch (const QuantityError& e) {
      r.fail(units, "mesh_units", e.what());
    }
  }
  p.loaded = meshes.get(p.mesh, p.mesh_scale, memory_budget_bytes);
}

// A point of the part table ([x, y, z] lengths), its default when absent and not required.
Eigen::Vector3d read_corner(BlockReader& r, const std::string& key, bool required) {
  const ParamInfo& info = find_param(part_params(), key);
  const YAML::Node node = r.take(key);
  if (!node.IsDefined()) {
    if (required) r.fail(node, key, "required key is missing (three lengths [x, y, z])");
    return Eigen::Vector3d::Zero();
  }
  const ParamValue::List v = r.value(node, info, ParamShape::kPoint, 3, {}).list();
  return {v[0].number(), v[1].number(), v[2].number()};
}

// An open-top box's walls: one thickness, or tiers [[z_top, thickness], ...] from the floor up.
void read_walls(BlockReader& r, PartSpec& p) {
  const ParamInfo& wall_info = find_param(part_params(), "open_box.wall");
  YAML::Node wall = r.take("open_box.wall");
  if (wall.IsSequence()) {
    for (std::size_t i = 0; i < wall.size(); ++i) {
      if (!wall[i].IsSequence() || wall[i].size() != 2)
        r.fail(wall[i], "open_box.wall", "expected a thickness or tiers [[z_top, thickness], ...]");
      p.tiers.push_back({r.parse(wall[i][0], Dimension::kLength, "open_box.wall"),
                         r.parse(wall[i][1], Dimension::kLength, "open_box.wall")});
      if (i > 0 && !(p.tiers[i].z_top_mm > p.tiers[i - 1].z_top_mm))
        r.fail(wall[i], "open_box.wall", "tier tops must increase from the floor up");
    }
    if (p.tiers.empty()) r.fail(wall, "open_box.wall", "expected at least one tier");
  } else {
    if (!wall.IsDefined()) r.fail(wall, "open_box.wall", "required key is missing (a length)");
    p.tiers.push_back({0.0, r.value(wall, wall_info, ParamShape::kNumber, 0, {}).number()});
  }
  for (const auto& tier : p.tiers)
    if (!(tier.wall_mm > 0) || 2 * tier.wall_mm >= std::min(p.size.x(), p.size.y()))
      r.fail(wall, "open_box.wall", "every wall must be positive and less than half the box's width");
}

// A box or an open-top box.
void read_box_part(BlockReader& r, PartSpec& p, bool open) {
  const std::string kind = open ? "open_box" : "box";
  p.kind = open ? PartSpec::Kind::kOpenBox : PartSpec::Kind::kBox;
  p.size = read_corner(r, kind + ".size", true);
  for (int i = 0; i < 3; ++i)
    if (!(p.size[i] > 0)) r.fail(r.take(kind + ".size"), kind + ".size", "every size must be positive");
  p.origin = read_corner(r, kind + ".origin", false);
  if (!open) return;
  read_walls(r, p);
  const YAML::Node floor = r.take("open_box.floor");
  if (!floor.IsDefined()) r.fail(floor, "open_box.floor", "required key is missing (a length)");
  p.floor_mm =
      r.value(floor, find_param(part_params(), "open_box.floor"), ParamShape::kNumber, 0, {}).number();
  if (p.floor_mm >= p.size.z()) r.fail(floor, "open_box.floor", "floor must be thinner than the box is tall");
}

}  // namespace

PartSpec read_part(BlockReader& r, const std::filesystem::path& dir, MeshCache& meshes,
                   double memory_budget_bytes) {
  PartSpec p;
  const bool has_mesh = r.has("mesh"), has_box = r.has("box"), has_open = r.has("open_box");
  if (has_mesh + has_box + has_open != 1)
    r.fail(YAML::Node(), "",
           "expected exactly one of: mesh (an STL, OBJ, 3MF, AMF or PLY file), box, open_box");
  if (has_mesh) {
    read_mesh_part(r, p, dir, meshes, memory_budget_bytes);
  } else {
    read_box_part(r, p, has_open);
    p.loaded = std::make_shared<const slicer::TriangleMesh>(
        has_open ? slicer::make_open_box(p.size, p.tiers, p.floor_mm, p.origin)
                 : slicer::make_box(p.size, p.origin));
  }
  r.finish(part_params());
  return p;
}

std::map<std::string, Tool> read_tools(const YAML::Node& node, const std::shared_ptr<YamlSource>& source,
                                       const std::map<std::string, SourceLocation>* overridden,
                                       const Material& material) {
  std::map<std::string, Tool> tools;
  if (!node.IsDefined() || node.IsNull()) return tools;
  if (!node.IsMap())
    throw InputError(location_of(node, source->file), "tools",
                     "expected a map of named tools {name: {bead_width, bead_thickness}}");
  for (auto it = node.begin(); it != node.end(); ++it) {
    const std::string name = it->first.Scalar();
    BlockReader r(it->second, "tools." + name, source, overridden);
    Tool tool;
    r.read(tool_params(), tool);
    if (YAML::Node m = r.take("material"); m.IsDefined() && (!m.IsScalar() || m.Scalar() != material.name))
      r.fail(
          m, "material",
          fmt::format("tool prints '{}' but the scenario's material is '{}' (one material per run for now)",
                      m.IsScalar() ? m.Scalar() : std::string("?"), material.name));
    if (tool.bead_width_mm < tool.bead_thickness_mm)
      r.fail(r.take("bead_width"), "bead_width", "a bead cannot be narrower than it is thick");
    r.finish(tool_params());
    tools[name] = tool;
  }
  return tools;
}

}  // namespace beadtwin::scenarios
