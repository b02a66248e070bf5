#include "scenarios/scenario.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "core/bead.hpp"
#include "core/hash.hpp"
#include "scenarios/embedded.hpp"
#include "scenarios/metrics.hpp"
#include "scenarios/params.hpp"
#include "scenarios/yaml_reader.hpp"
#include "slicer/gcode_reader.hpp"

namespace beadtwin::scenarios {
namespace {

constexpr std::string_view kBuiltIn = "<built-in>";

const ParamSpec& spec(std::span<const ParamSpec> table, std::string_view key) {
  for (const auto& s : table)
    if (s.key == key) return s;
  throw InternalError(fmt::format("no parameter '{}' declared", key));
}

// The value of `values` whose name (to_string) is `text`; otherwise an error at `key` listing the names.
template <typename Enum, std::size_t N>
Enum one_of(BlockReader& r, std::string_view key, const std::string& text, const Enum (&values)[N]) {
  std::string names;
  for (const Enum v : values) {
    if (to_string(v) == text) return v;
    names += fmt::format("{}{}", names.empty() ? "" : ", ", to_string(v));
  }
  r.fail(r.take(key), key, fmt::format("expected one of {} but found '{}'", names, text));
}

// A list item's name: its `name` when it is a map with a scalar one. yaml-cpp throws when a scalar or a list
// is asked for a key, so an item that is not a map must not be asked.
std::optional<std::string> item_name(const YAML::Node& item) {
  if (!item.IsMap()) return std::nullopt;
  const YAML::Node name = item["name"];
  if (!name || !name.IsScalar()) return std::nullopt;
  return name.Scalar();
}

// A path that exists but is no regular file (a named pipe, a device, a folder): reading it could wait for
// ever or mean nothing, so it is refused rather than opened.
bool is_special_file(const std::filesystem::path& path) {
  std::error_code ec;
  return std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec);
}

}  // namespace

// Scenario, machine, material and gate files are text people write: a few kB. One far larger is not one of
// them (a mesh or a program named by mistake), and yaml-cpp takes some fifty times a file's size to hold it.
constexpr std::uintmax_t kMaxTextFileBytes = 16u << 20;

std::string read_text_file(const std::filesystem::path& path, const SourceLocation& from,
                           const std::string& key) {
  if (is_special_file(path))
    throw InputError(from, key, fmt::format("'{}' is not a regular file", path.string()));
  std::error_code ec;
  if (const std::uintmax_t bytes = std::filesystem::file_size(path, ec); !ec && bytes > kMaxTextFileBytes)
    throw InputError(
        from, key,
        fmt::format("'{}' is {:.1f} MB, too large for a YAML settings file (at most {} MB); is it "
                    "the right file?",
                    path.string(), static_cast<double>(bytes) / (1 << 20), kMaxTextFileBytes >> 20));
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(from, key, fmt::format("cannot open '{}'", path.string()));
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

namespace {

// A machine or material file: found beside the scenario, or among the shipped ones.
struct LibraryFile {
  std::string text;
  std::string file;  // for messages
};

LibraryFile find_library_file(const std::string& kind, const std::string& name,
                              const std::filesystem::path& scenario_dir, const SourceLocation& from) {
  if (name.empty() || name.find_first_of("/\\") != std::string::npos || name.starts_with("."))
    throw InputError(
        from, kind,
        fmt::format("'{}' is not a {} name (use a name such as the file name without .yaml)", name, kind));
  const std::string rel = fmt::format("{}s/{}.yaml", kind, name);
  if (!scenario_dir.empty()) {
    const std::filesystem::path local = scenario_dir / rel;
    if (std::filesystem::exists(local)) return {read_text_file(local, from, kind), local.string()};
  }
  const auto& shipped = shipped_files();
  const auto it = shipped.find(rel);
  if (it != shipped.end()) return {it->second, std::string(kBuiltIn) + "/" + rel};
  std::string names;
  const std::string prefix = kind + "s/";
  for (const auto& [path, text] : shipped)
    if (path.starts_with(prefix))
      names += (names.empty() ? "" : ", ") + path.substr(prefix.size(), path.size() - prefix.size() - 5);
  throw InputError(
      from, kind,
      fmt::format("no {} named '{}' (looked for {} beside the scenario and among the shipped ones: {})", kind,
                  name, rel, names));
}

// The blocks of a scenario after variant overrides, each with the file it came from.
struct Tree {
  YAML::Node root;
  std::shared_ptr<YamlSource> scenario_src;
  YAML::Node machine;
  std::shared_ptr<YamlSource> machine_src;
  YAML::Node material;
  std::shared_ptr<YamlSource> material_src;
  std::map<std::string, SourceLocation> overridden;
};

std::shared_ptr<YamlSource> library_source(YAML::Node& node, const std::string& file) {
  auto src = std::make_shared<YamlSource>();
  src->file = file;
  if (node.IsMap() && node["units"]) {
    src->default_units = read_units_block(node["units"], file);
    node.remove("units");
  }
  return src;
}

// machine: NAME | {inline map}
YAML::Node resolve_library(const YAML::Node& root, const std::string& kind,
                           const std::shared_ptr<YamlSource>& scenario_src, const std::filesystem::path& dir,
                           std::shared_ptr<YamlSource>& src_out) {
  const YAML::Node ref = root[kind];
  const SourceLocation at = location_of(ref.IsDefined() ? ref : root, scenario_src->file);
  if (!ref.IsDefined() || ref.IsNull())
    throw InputError(at, kind, fmt::format("required key is missing (the {} to use)", kind));
  if (ref.IsMap()) {
    src_out = scenario_src;
    return YAML::Clone(ref);
  }
  if (!ref.IsScalar())
    throw InputError(at, kind, fmt::format("expected the name of a {} file or an inline map", kind));
  const LibraryFile lib = find_library_file(kind, ref.Scalar(), dir, at);
  YAML::Node node = parse_yaml(lib.text, lib.file);
  if (!node.IsMap())
    throw InputError({lib.file, 1, 1}, {}, fmt::format("a {} file must be a map of keys and values", kind));
  src_out = library_source(node, lib.file);
  return node;
}

// How the machine's programs are read: its dialect and extruder, and its roller engaged from the start when
// it has a roller or tamper but no codes for it.
slicer::ReaderOptions reader_options(const Machine& m, const Extruder* extruder) {
  slicer::ReaderOptions o = slicer::reader_options_for(m.dialect, extruder);
  o.max_macro_steps = m.macro_step_limit;
  o.roller_down_at_start =
      (m.kind == "roller-gantry" || m.kind == "tamper-gantry") && m.dialect.roller_down.empty();
  return o;
}

Machine read_machine(BlockReader& r) {
  const auto t = machine_params();
  Machine m;
  m.name = r.string(spec(t, "name"));
  m.description = r.string(spec(t, "description"));
  m.kind = r.string(spec(t, "kind"));
  static const std::string_view kinds[] = {"roller-gantry", "tamper-gantry", "robot", "desktop"};
  if (std::find(std::begin(kinds), std::end(kinds), m.kind) == std::end(kinds))
    r.fail(r.take("kind"), "kind",
           fmt::format("unknown machine kind '{}'; expected roller-gantry, tamper-gantry, robot or desktop",
                       m.kind));
  m.motion.max_feed_mm_s = r.quantity(spec(t, "max_feed"));
  m.motion.max_travel_mm_s = r.quantity(spec(t, "max_travel"));
  m.motion.acceleration_mm_s2 = r.quantity(spec(t, "acceleration"));
  m.motion.junction_deviation_mm = r.quantity(spec(t, "junction_deviation"));
  m.roller_width_mm = r.quantity(spec(t, "roller.width"));
  m.roller_diameter_mm = r.quantity(spec(t, "roller.diameter"));
  m.nozzle_diameter_mm = r.quantity(spec(t, "nozzle_diameter"));
  m.extruder_output_kg_s = r.quantity(spec(t, "extruder.output"));
  m.extruder_max_output_kg_s = r.quantity(spec(t, "extruder.max_output"));
  {
    const std::string kind = r.string(spec(t, "extruder.kind"));
    if (kind == "gear_pump")
      m.extruder.kind = ExtruderKind::kGearPump;
    else if (kind == "screw")
      m.extruder.kind = ExtruderKind::kScrew;
    else if (kind == "filament")
      m.extruder.kind = ExtruderKind::kFilament;
    else
      r.fail(r.take("extruder.kind"), "extruder.kind",
             fmt::format("expected gear_pump, screw or filament but found '{}'", kind));
  }
  m.extruder.displacement_mm3_per_rev = r.quantity(spec(t, "extruder.displacement"));
  m.extruder.filament_diameter_mm = r.quantity(spec(t, "extruder.filament_diameter"));
  m.extruder.max_rpm = r.quantity(spec(t, "extruder.max_rpm"));
  m.extruder.constant_feed_mm_s = r.quantity(spec(t, "extruder.constant_feed"));
  m.ooze_time_s = r.quantity(spec(t, "extruder.ooze_time"));
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
  m.environment.ambient_c = r.quantity(spec(t, "environment.ambient"));
  m.environment.bed_temp_c = r.quantity(spec(t, "environment.bed_temp"));
  m.environment.bed_insulated = r.boolean(spec(t, "environment.bed_insulated"));
  m.environment.convection_W_m2K = r.quantity(spec(t, "environment.convection"));
  if (YAML::Node profile = r.take("environment.convection_by_height"); profile.IsDefined()) {
    const ParamSpec& s = spec(t, "environment.convection_by_height");
    const std::string key = "environment.convection_by_height";
    if (!profile.IsSequence() || profile.size() == 0)
      r.fail(profile, key, "expected a list of [height, h] points, such as [[0 m, 7], [2 m, 12]]");
    for (const YAML::Node& p : profile) {
      if (!p.IsSequence() || p.size() != 2) r.fail(p, key, "expected a point [height, h]");
      const double height = r.parse(p[0], Dimension::kLength, key);
      const double h = r.parse(p[1], s.dim, key);
      r.check_range(s, h, p[1]);
      if (!m.environment.convection_by_height.empty() &&
          height <= m.environment.convection_by_height.back().first)
        r.fail(p, key, "heights must increase from one point to the next");
      m.environment.convection_by_height.emplace_back(height, h);
    }
  }
  m.environment.bed_contact_W_m2K = r.quantity(spec(t, "environment.bed_contact"));
  const std::string units = r.string(spec(t, "gcode.units"));
  if (units != "in" && units != "mm")
    r.fail(r.take("gcode.units"), "gcode.units", fmt::format("expected in or mm but found '{}'", units));
  m.dialect.inches = units == "in";
  m.dialect.arcs = r.boolean(spec(t, "gcode.arcs"));
  // Codes a machine does not have are "none" (written as comments).
  auto code = [&](std::string_view key) {
    std::string c = r.string(spec(t, key));
    return c == "none" ? std::string() : c;
  };
  m.dialect.melt_on = code("gcode.melt_on");
  m.dialect.melt_off = code("gcode.melt_off");
  m.dialect.roller_down = code("gcode.roller_down");
  m.dialect.roller_up = code("gcode.roller_up");
  if (m.dialect.roller_down.empty() != m.dialect.roller_up.empty())
    r.fail(r.take(m.dialect.roller_down.empty() ? "gcode.roller_up" : "gcode.roller_down"),
           m.dialect.roller_down.empty() ? "gcode.roller_up" : "gcode.roller_down",
           "give both roller codes (down and up), or neither");
  m.dialect.heat_on = code("gcode.heat_on");
  m.dialect.heat_off = code("gcode.heat_off");
  m.dialect.prime_code = code("gcode.prime_code");
  m.dialect.reverse_on = code("gcode.reverse_on");
  m.dialect.reverse_off = code("gcode.reverse_off");
  m.dialect.rpm_word = r.string(spec(t, "gcode.rpm_word"));
  m.dialect.macro_loops = r.boolean(spec(t, "gcode.macro_loops"));
  m.macro_step_limit = r.integer(spec(t, "gcode.macro_step_limit"));
  m.dialect.absolute_e = r.boolean(spec(t, "gcode.absolute_e"));
  if (r.boolean(spec(t, "gcode.rapid_g0"))) m.dialect.rapid_feed_mm_s = m.motion.max_travel_mm_s;
  if (m.extruder.has_constant_feed() && (m.dialect.melt_on.empty() || m.dialect.melt_off.empty()))
    r.fail(
        r.take("extruder.constant_feed"), "extruder.constant_feed",
        "a constant feed runs from melt on to melt off: give the machine gcode.melt_on and gcode.melt_off");
  r.finish(t);
  return m;
}

Material read_material(BlockReader& r) {
  const auto t = material_params();
  Material m;
  m.name = r.string(spec(t, "name"));
  (void)r.string(spec(t, "description"));
  m.density_kg_m3 = r.quantity(spec(t, "density"));
  m.specific_heat_J_kgK = r.quantity(spec(t, "specific_heat"));
  if (YAML::Node table = r.take("specific_heat_by_temp"); table.IsDefined()) {
    const ParamSpec& s = spec(t, "specific_heat_by_temp");
    const std::string key = "specific_heat_by_temp";
    if (!table.IsSequence() || table.size() == 0)
      r.fail(table, key,
             "expected a list of [temperature, c_p] points, such as [[25 C, 1400], [200 C, 2000]]");
    for (const YAML::Node& p : table) {
      if (!p.IsSequence() || p.size() != 2) r.fail(p, key, "expected a point [temperature, c_p]");
      const double temp = r.parse(p[0], Dimension::kTemperature, key);
      const double cp = r.parse(p[1], s.dim, key);
      r.check_range(s, cp, p[1]);
      if (!m.specific_heat_by_temp.empty() && temp <= m.specific_heat_by_temp.back().first)
        r.fail(p, key, "temperatures must increase from one point to the next");
      m.specific_heat_by_temp.emplace_back(temp, cp);
    }
  }
  m.conductivity_along_W_mK = r.quantity(spec(t, "conductivity.along"));
  m.conductivity_across_W_mK = r.quantity(spec(t, "conductivity.across"));
  m.conductivity_through_W_mK = r.quantity(spec(t, "conductivity.through"));
  m.emissivity = r.quantity(spec(t, "emissivity"));
  m.deposition_temp_c = r.quantity(spec(t, "deposition_temp"));
  m.glass_transition_c = r.quantity(spec(t, "glass_transition"));
  m.support_limit_c = r.quantity(spec(t, "fusion.support_limit"));
  m.healing_ref_temp_c = r.quantity(spec(t, "fusion.healing_ref_temp"));
  m.reptation_time_ref_s = r.quantity(spec(t, "fusion.reptation_time"));
  m.healing_activation_J_mol = r.quantity(spec(t, "fusion.activation_energy"));
  m.healing_min_temp_c = r.quantity(spec(t, "fusion.min_healing_temp"));
  m.required_healing = r.quantity(spec(t, "fusion.required_healing"));
  m.price_per_kg = r.quantity(spec(t, "price"));
  // Sources of the values: free text kept with the file, read here so it is not an unknown key.
  (void)r.take("sources");
  static constexpr std::string_view kExtra[] = {"sources"};
  r.finish(t, kExtra);
  return m;
}

Eigen::Vector3d read_vector(BlockReader& r, const std::string& key, bool required) {
  YAML::Node node = r.take(key);
  if (!node.IsDefined()) {
    if (required) r.fail(node, key, "required key is missing (three lengths [x, y, z])");
    return Eigen::Vector3d::Zero();
  }
  if (!node.IsSequence() || node.size() != 3) r.fail(node, key, "expected three lengths [x, y, z]");
  Eigen::Vector3d v;
  for (std::size_t i = 0; i < 3; ++i)
    v[static_cast<Eigen::Index>(i)] = r.parse(node[i], Dimension::kLength, key);
  return v;
}

// A list of whole numbers [a, b, ...] (absent: the spec's default), each in the spec's range, none twice.
std::vector<int> read_integer_list(BlockReader& r, const ParamSpec& spec) {
  const YAML::Node node = r.take(spec.key);
  const bool given = node.IsDefined() && !node.IsNull();
  const YAML::Node list = given ? node : YAML::Load(std::string(spec.default_text));
  if (!list.IsSequence())
    r.fail(node, spec.key, fmt::format("expected a list of whole numbers such as {}", spec.default_text));
  std::vector<int> out;
  for (const YAML::Node& item : list) {
    const long v = r.whole_number(item.IsScalar() ? item.Scalar() : "", item, spec.key);
    r.check_range(spec, static_cast<double>(v), item);
    if (std::find(out.begin(), out.end(), v) != out.end())
      r.fail(item, spec.key, fmt::format("{} is in the list twice", v));
    out.push_back(static_cast<int>(v));
  }
  return out;
}

// Meshes read while loading, shared by the variants that use the same file at the same scale, with the
// repairs their reading reported.
struct MeshCache {
  std::map<std::pair<std::string, double>, std::shared_ptr<const slicer::TriangleMesh>> meshes;
  std::vector<std::string> warnings;

  std::shared_ptr<const slicer::TriangleMesh> get(const std::filesystem::path& path, double scale,
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
};

PartSpec read_part(BlockReader& r, const std::filesystem::path& dir, MeshCache& meshes,
                   double memory_budget_bytes) {
  PartSpec p;
  const ParamSpec kLen{"", ParamType::kQuantity, Dimension::kLength, "", 0, 1e5, true, "", ""};
  auto length = [&](const std::string& key) {
    YAML::Node node = r.take(key);
    if (!node.IsDefined()) r.fail(node, key, "required key is missing (a length)");
    const double v = r.parse(node, Dimension::kLength, key);
    ParamSpec s = kLen;
    s.key = key;
    r.check_range(s, v, node);
    return v;
  };
  const bool has_mesh = r.has("mesh"), has_box = r.has("box"), has_open = r.has("open_box");
  if (has_mesh + has_box + has_open != 1)
    r.fail(YAML::Node(), "",
           "expected exactly one of: mesh (an STL, OBJ, 3MF, AMF or PLY file), box, open_box");
  if (has_mesh) {
    p.kind = PartSpec::Kind::kMesh;
    YAML::Node node = r.take("mesh");
    if (!node.IsScalar())
      r.fail(node, "mesh", "expected the path of a mesh file (STL, OBJ, 3MF, AMF or PLY)");
    p.mesh = dir / node.Scalar();
    if (!std::filesystem::exists(p.mesh))
      r.fail(node, "mesh", fmt::format("no such file: {}", p.mesh.string()));
    YAML::Node units = r.take("mesh_units");
    if (units.IsDefined()) {
      try {
        p.mesh_scale = to_internal(1.0, units.Scalar(), Dimension::kLength);
      } catch (const QuantityError& e) {
        r.fail(units, "mesh_units", e.what());
      }
    }
    p.loaded = meshes.get(p.mesh, p.mesh_scale, memory_budget_bytes);
  } else {
    const std::string kind = has_box ? "box" : "open_box";
    p.kind = has_box ? PartSpec::Kind::kBox : PartSpec::Kind::kOpenBox;
    p.size = read_vector(r, kind + ".size", true);
    for (int i = 0; i < 3; ++i)
      if (!(p.size[i] > 0)) r.fail(r.take(kind + ".size"), kind + ".size", "every size must be positive");
    p.origin = read_vector(r, kind + ".origin", false);
    if (!has_box) {
      // wall: a thickness, or tiers [[z_top, thickness], ...] from the floor up (walls thinning inside).
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
        p.tiers.push_back({0.0, length("open_box.wall")});
      }
      p.floor_mm = length("open_box.floor");
      for (const auto& tier : p.tiers)
        if (!(tier.wall_mm > 0) || 2 * tier.wall_mm >= std::min(p.size.x(), p.size.y()))
          r.fail(wall, "open_box.wall", "every wall must be positive and less than half the box's width");
      if (p.floor_mm >= p.size.z())
        r.fail(r.take("open_box.floor"), "open_box.floor", "floor must be thinner than the box is tall");
    }
  }
  static constexpr std::string_view kKeys[] = {"mesh",          "mesh_units",    "box.size",
                                               "box.origin",    "open_box.size", "open_box.origin",
                                               "open_box.wall", "open_box.floor"};
  r.finish({}, kKeys);
  return p;
}

// The part as a mesh: a built-in primitive (a mesh file is read into `loaded` by read_part).
slicer::TriangleMesh build_part_mesh(const PartSpec& part) {
  switch (part.kind) {
    case PartSpec::Kind::kBox:
      return slicer::make_box(part.size, part.origin);
    case PartSpec::Kind::kOpenBox:
      return slicer::make_open_box(part.size, part.tiers, part.floor_mm, part.origin);
    case PartSpec::Kind::kNone:
      return {};
    case PartSpec::Kind::kMesh:
      break;
  }
  throw InternalError("a mesh part is read when it is loaded");
}

// A tool / melt configuration (patent (48)): the bead a section lays when it names the tool.
struct Tool {
  double bead_width_mm = 0.0;
  double bead_thickness_mm = 0.0;
};

std::map<std::string, Tool> read_tools(const Tree& tree, const Material& material) {
  std::map<std::string, Tool> tools;
  const YAML::Node node = tree.root["tools"];
  if (!node.IsDefined() || node.IsNull()) return tools;
  if (!node.IsMap())
    throw InputError(location_of(node, tree.scenario_src->file), "tools",
                     "expected a map of named tools {name: {bead_width, bead_thickness}}");
  const auto t = tool_params();
  for (auto it = node.begin(); it != node.end(); ++it) {
    const std::string name = it->first.Scalar();
    BlockReader r(it->second, "tools." + name, tree.scenario_src, &tree.overridden);
    (void)r.string(spec(t, "description"));
    if (YAML::Node m = r.take("material"); m.IsDefined() && (!m.IsScalar() || m.Scalar() != material.name))
      r.fail(
          m, "material",
          fmt::format("tool prints '{}' but the scenario's material is '{}' (one material per run for now)",
                      m.IsScalar() ? m.Scalar() : std::string("?"), material.name));
    Tool tool;
    tool.bead_width_mm = r.quantity(spec(t, "bead_width"));
    tool.bead_thickness_mm = r.quantity(spec(t, "bead_thickness"));
    if (tool.bead_width_mm < tool.bead_thickness_mm)
      r.fail(r.take("bead_width"), "bead_width", "a bead cannot be narrower than it is thick");
    r.finish(t);
    tools[name] = tool;
  }
  return tools;
}

// `part` is the part's mesh (for `z: part` and `body`).
slicer::SectionParams read_section(BlockReader& r, const Machine& machine, const Material& material,
                                   const slicer::TriangleMesh& part,
                                   const std::map<std::string, Tool>& tools) {
  const auto t = section_params();
  slicer::SectionParams s;
  s.name = r.string(spec(t, "name"));
  // A polygon [[x, y], ...] with at least `min_points` points.
  auto points = [](BlockReader& br, const YAML::Node& node, std::string_view key, std::size_t min_points) {
    if (!node.IsSequence() || node.size() < min_points)
      br.fail(node, key, fmt::format("expected at least {} points [[x, y], ...]", min_points));
    slicer::Polygon poly;
    for (const auto& p : node) {
      if (!p.IsSequence() || p.size() != 2) br.fail(p, key, "expected a point [x, y]");
      poly.emplace_back(br.parse(p[0], Dimension::kLength, std::string(key)),
                        br.parse(p[1], Dimension::kLength, std::string(key)));
      // As for a part: beyond 100 m is a mistake of units, and far beyond it the polygon clipper's integer
      // range ends (found by tests/fuzz: an exception that ended the program).
      if (!(std::abs(poly.back().x()) <= slicer::kMaxPartSizeMm &&
            std::abs(poly.back().y()) <= slicer::kMaxPartSizeMm))
        br.fail(
            p, key,
            fmt::format("the point ({:.6g}, {:.6g}) mm is more than {:g} m from the origin; are the units "
                        "right?",
                        poly.back().x(), poly.back().y(), slicer::kMaxPartSizeMm / 1000));
    }
    return poly;
  };
  if (YAML::Node body = r.take("body"); body.IsDefined()) {
    if (!body.IsScalar() || body.Scalar().empty())
      r.fail(body, "body", "expected the name of one of the part's bodies");
    s.body = body.Scalar();
    if (slicer::find_body(part, s.body) < 0)
      r.fail(body, "body",
             fmt::format("the part has no body named '{}'; its bodies are: {}", s.body,
                         slicer::body_list(part)));
  }
  // AM Outline (patent (39)): a 2-D path printed as it is.
  if (YAML::Node outline = r.take("outline"); outline.IsDefined()) {
    BlockReader orr(outline, r.full_key("outline"), std::make_shared<YamlSource>(r.source()));
    s.outline_path = points(orr, orr.take("points"), "points", 2);
    ParamSpec closed = spec(t, "outline.closed");
    closed.key = "closed";  // inside the outline block
    s.outline_closed = orr.boolean(closed);
    static constexpr std::string_view kOutlineKeys[] = {"points", "closed"};
    orr.finish({}, kOutlineKeys);
  }
  // Variable layer height with constant feed (seed 002): outline sections only.
  if (YAML::Node vh = r.take("variable_height"); vh.IsDefined()) {
    if (s.outline_path.empty())
      r.fail(vh, "variable_height", "a variable layer height needs an AM Outline section (outline: points)");
    BlockReader vr(vh, r.full_key("variable_height"), std::make_shared<YamlSource>(r.source()));
    ParamSpec slope = spec(t, "variable_height.slope");
    slope.key = "slope";
    s.height_slope = vr.quantity(slope);
    if (YAML::Node d = vr.take("direction"); d.IsDefined()) {
      if (!d.IsSequence() || d.size() != 2) vr.fail(d, "direction", "expected a direction [x, y]");
      s.height_direction = {vr.parse(d[0], Dimension::kDimensionless, "direction"),
                            vr.parse(d[1], Dimension::kDimensionless, "direction")};
      if (!(s.height_direction.norm() > 0)) vr.fail(d, "direction", "expected a non-zero direction [x, y]");
    }
    static constexpr std::string_view kKeys[] = {"slope", "direction"};
    vr.finish({}, kKeys);
  }
  // Containment boundaries (patent (41)): one outside polygon, and one or more inside polygons.
  if (YAML::Node c = r.take("containment"); c.IsDefined()) {
    BlockReader cr(c, r.full_key("containment"), std::make_shared<YamlSource>(r.source()));
    if (YAML::Node out = cr.take("outside"); out.IsDefined())
      s.containment_outside = slicer::union_nonzero({points(cr, out, "outside", 3)});
    if (YAML::Node in = cr.take("inside"); in.IsDefined()) {
      const bool many =
          in.IsSequence() && in.size() > 0 && in[0].IsSequence() && in[0].size() > 0 && in[0][0].IsSequence();
      slicer::Polygons polys;
      if (many)
        for (const auto& one : in) polys.push_back(points(cr, one, "inside", 3));
      else
        polys.push_back(points(cr, in, "inside", 3));
      s.containment_inside = slicer::union_nonzero(polys);
    }
    static constexpr std::string_view kContainmentKeys[] = {"outside", "inside"};
    cr.finish({}, kContainmentKeys);
  }
  {
    const std::string plane = r.string(spec(t, "slice_plane"));
    s.slice_plane = one_of(r, "slice_plane", plane, slicer::kSlicePlanes);
  }
  if (YAML::Node w = r.take("shares_wall_with"); w.IsDefined()) {
    if (!w.IsScalar() || w.Scalar().empty())
      r.fail(w, "shares_wall_with", "expected the name of another section");
    s.shares_wall_with = w.Scalar();
  }
  YAML::Node z = r.take("z");
  YAML::Node layers = r.take("layers");
  if (!z.IsDefined() && !(layers.IsDefined() && !s.outline_path.empty()))
    r.fail(
        z, "z",
        "required key is missing (Z limits [lower, upper], or 'part'; an outline section may give layers)");
  if (z.IsDefined() && layers.IsDefined()) r.fail(layers, "layers", "give either z or layers, not both");
  if (!z.IsDefined()) {
    // Set from `layers` once the layer height is known (below).
  } else if (z.IsScalar() && z.Scalar() == "part") {
    // The full part (patent (42)): from the bottom of the section's body (or of the part) to its top.
    const int body = s.body.empty() ? -1 : slicer::find_body(part, s.body);
    const slicer::TriangleMesh m =
        slicer::lay_down(body < 0 ? part : slicer::select_body(part, body), s.slice_plane);
    s.z_min_mm = m.min_corner().z();
    s.z_max_mm = m.max_corner().z();
  } else {
    if (!z.IsSequence() || z.size() != 2) r.fail(z, "z", "expected Z limits [lower, upper] or 'part'");
    s.z_min_mm = r.parse(z[0], Dimension::kLength, "z");
    s.z_max_mm = r.parse(z[1], Dimension::kLength, "z");
    if (!(s.z_max_mm > s.z_min_mm))
      r.fail(z, "z", fmt::format("upper limit {} mm is not above lower limit {} mm", s.z_max_mm, s.z_min_mm));
  }
  // The bead: from the section, else from its tool (patent (48)), else the defaults.
  const Tool* tool = nullptr;
  if (YAML::Node tn = r.take("tool"); tn.IsDefined()) {
    const auto found = tn.IsScalar() ? tools.find(tn.Scalar()) : tools.end();
    if (found == tools.end()) {
      std::string names;
      for (const auto& [n, _] : tools) names += (names.empty() ? "" : ", ") + n;
      r.fail(tn, "tool",
             fmt::format("no tool named '{}' under tools: (there are: {})", tn.IsScalar() ? tn.Scalar() : "?",
                         names.empty() ? "none" : names));
    }
    tool = &found->second;
  }
  const auto height = r.optional_quantity(spec(t, "layer_height"));
  const auto width = r.optional_quantity(spec(t, "bead_width"));
  s.layer_height_mm = height ? *height
                      : tool ? tool->bead_thickness_mm
                             : parse_quantity(spec(t, "layer_height").default_text, Dimension::kLength);
  s.bead_width_mm = width  ? *width
                    : tool ? tool->bead_width_mm
                           : parse_quantity(spec(t, "bead_width").default_text, Dimension::kLength);
  if (s.bead_width_mm < s.layer_height_mm)
    r.fail(r.take("bead_width"), "bead_width",
           fmt::format("bead width {} mm is less than the layer height {} mm", s.bead_width_mm,
                       s.layer_height_mm));
  if (layers.IsDefined()) {
    s.z_min_mm = 0.0;
    s.z_max_mm = r.integer(spec(t, "layers")) * s.layer_height_mm;
  }
  constexpr double kMaxLayers = 20000;  // a 3 m part at 0.15 mm: far beyond any real section
  if ((s.z_max_mm - s.z_min_mm) / s.layer_height_mm > kMaxLayers)
    r.fail(r.has("layer_height") ? r.take("layer_height") : YAML::Node(), "layer_height",
           fmt::format("{} mm layers over {} mm make {:.0f} layers; at most {:.0f} are allowed",
                       s.layer_height_mm, s.z_max_mm - s.z_min_mm,
                       (s.z_max_mm - s.z_min_mm) / s.layer_height_mm, kMaxLayers));
  const double area = bead_area_mm2(s.bead_width_mm, s.layer_height_mm);
  const double nominal_flow_mm3_s = machine.extruder_output_kg_s / material.density_kg_m3 * 1e9;
  s.print_speed_mm_s = r.optional_quantity(spec(t, "speed")).value_or(nominal_flow_mm3_s / area);
  const double max_flow_mm3_s = machine.extruder_max_output_kg_s / material.density_kg_m3 * 1e9;
  if (s.print_speed_mm_s * area > max_flow_mm3_s * (1 + 1e-9))
    r.fail(r.take("speed"), "speed",
           fmt::format("needs {:.0f} mm3/s of material but the extruder gives at most {:.0f} mm3/s",
                       s.print_speed_mm_s * area, max_flow_mm3_s));
  s.travel_speed_mm_s = r.optional_quantity(spec(t, "travel_speed")).value_or(machine.motion.max_travel_mm_s);
  if (YAML::Node sp = r.take("start_point"); sp.IsDefined()) {
    if (!sp.IsSequence() || sp.size() != 2) r.fail(sp, "start_point", "expected two lengths [x, y]");
    s.start_point_mm = {r.parse(sp[0], Dimension::kLength, "start_point"),
                        r.parse(sp[1], Dimension::kLength, "start_point")};
  }
  s.seam_offset_mm = r.quantity(spec(t, "seam_offset"));
  s.boundary.reverse_alternate = r.boolean(spec(t, "boundary.reverse_alternate"));
  s.boundary.lead_in_mm = r.quantity(spec(t, "boundary.lead_in"));
  s.boundary.lead_out_mm = r.quantity(spec(t, "boundary.lead_out"));
  s.boundary.tangential_lead_out = r.boolean(spec(t, "boundary.force_tangential_lead_out"));
  s.chord_tolerance_mm = r.quantity(spec(t, "chord_tolerance"));
  s.min_polygon_area_mm2 = r.quantity(spec(t, "min_polygon_area"));
  s.contact_offset_mm = r.quantity(spec(t, "contact_offset"));
  if (YAML::Node sh = r.take("shift"); sh.IsDefined()) {
    if (!sh.IsSequence() || sh.size() != 2) r.fail(sh, "shift", "expected two lengths [dx, dy]");
    s.shift_mm = {r.parse(sh[0], Dimension::kLength, "shift"), r.parse(sh[1], Dimension::kLength, "shift")};
  }
  s.outer_stock_mm = r.quantity(spec(t, "outer_stock"));
  s.inner_stock_mm = r.quantity(spec(t, "inner_stock"));
  s.merge_slices = r.boolean(spec(t, "merge_slices"));
  s.ignore_inner_contours = r.boolean(spec(t, "ignore_inner_contours"));
  const std::string order = r.string(spec(t, "layer_order"));
  if (order != "boundary_first" && order != "fill_first")
    r.fail(r.take("layer_order"), "layer_order",
           fmt::format("expected boundary_first or fill_first but found '{}'", order));
  s.fill_first = order == "fill_first";
  s.clearance_height_mm = r.quantity(spec(t, "clearance_height"));
  s.initial_clearance_height_mm = r.quantity(spec(t, "initial_clearance_height"));
  s.melt_reduction = r.quantity(spec(t, "melt_reduction"));
  s.rafts = r.integer(spec(t, "rafts"));
  s.stock_on_top = r.integer(spec(t, "stock_on_top"));
  s.boundary.start_stop_overlap = r.quantity(spec(t, "boundary.start_stop_overlap"));
  s.boundary.min_pass_length_mm = r.quantity(spec(t, "boundary.min_pass_length"));
  s.boundary.thin_walls = r.boolean(spec(t, "boundary.thin_walls"));
  s.boundary.thin_wall_max_width_mm = r.quantity(spec(t, "boundary.thin_wall_max_width"));
  s.boundary.thin_wall_one_bead_width_mm = r.quantity(spec(t, "boundary.thin_wall_one_bead_width"));
  s.boundary.thin_wall_thickness_deviation_mm = r.quantity(spec(t, "boundary.thin_wall_thickness_deviation"));
  s.boundary.thin_wall_stitching_gap_mm = r.quantity(spec(t, "boundary.thin_wall_stitching_gap"));
  s.boundary.thin_wall_intersection_distance_mm =
      r.quantity(spec(t, "boundary.thin_wall_intersection_distance"));
  s.boundary.passes = r.integer(spec(t, "boundary.passes"));
  s.boundary.overlap = r.quantity(spec(t, "boundary.overlap"));
  s.boundary.max_overlap = r.quantity(spec(t, "boundary.max_overlap"));
  if (s.boundary.max_overlap < s.boundary.overlap)
    r.fail(r.take("boundary.max_overlap"), "boundary.max_overlap",
           fmt::format("maximum pass overlap {:.0f} % is below the pass overlap {:.0f} %",
                       100 * s.boundary.max_overlap, 100 * s.boundary.overlap));
  s.combine_stock_offset = r.boolean(spec(t, "combine_stock_offset"));
  s.arc_chord_tolerance_mm = r.quantity(spec(t, "arc_chord_tolerance"));
  s.melt.prime = r.boolean(spec(t, "melt_on.prime"));
  s.melt.delay_during_prime = r.boolean(spec(t, "melt_on.delay_during_prime"));
  s.melt.prime_time_s = r.quantity(spec(t, "melt_on.prime_time"));
  s.melt.prime_rpm = r.quantity(spec(t, "melt_on.prime_rpm"));
  s.melt.coast = r.boolean(spec(t, "melt_off.coast"));
  s.melt.coast_distance_mm = r.quantity(spec(t, "melt_off.coast_distance"));
  s.melt.reverse = r.boolean(spec(t, "melt_off.reverse"));
  s.melt.reverse_during_coast = r.boolean(spec(t, "melt_off.reverse_during_coast"));
  s.melt.delay_during_reverse = r.boolean(spec(t, "melt_off.delay_during_reverse"));
  s.melt.reverse_time_s = r.quantity(spec(t, "melt_off.reverse_time"));
  s.melt.reverse_rpm = r.quantity(spec(t, "melt_off.reverse_rpm"));
  s.melt.set_at_control = r.boolean(spec(t, "melt_set_at_control"));
  if ((s.melt.prime && s.melt.prime_rpm > 0) || (s.melt.reverse && s.melt.reverse_rpm > 0))
    if (!machine.extruder.has_rpm())
      r.fail(r.take(s.melt.prime ? "melt_on.prime_rpm" : "melt_off.reverse_rpm"),
             s.melt.prime ? "melt_on.prime_rpm" : "melt_off.reverse_rpm",
             fmt::format("machine '{}' gives no extruder displacement (extruder.displacement), so a speed in "
                         "rev/min means no flow",
                         machine.name));
  s.pull_back.length_mm = r.quantity(spec(t, "pull_back.length"));
  s.pull_back.extension_mm = r.quantity(spec(t, "pull_back.extension"));
  s.pull_back.min_turn_deg = r.quantity(spec(t, "pull_back.min_turn"));
  s.smoothing.smooth_curves = r.boolean(spec(t, "smoothing.smooth_curves"));
  s.smoothing.never_start_in_corner = r.boolean(spec(t, "smoothing.never_start_in_corner"));
  s.smoothing.min_polygon_angle_deg = r.quantity(spec(t, "smoothing.min_polygon_angle"));
  s.voids.detect = r.boolean(spec(t, "voids.detect"));
  s.voids.fill = r.boolean(spec(t, "voids.fill"));
  s.voids.min_width_mm = r.quantity(spec(t, "voids.min_width"));
  s.boundary.inside_out = r.boolean(spec(t, "boundary.inside_out"));
  // fill: none | {style, angle, ...}. The keys are read (with defaults) either way.
  YAML::Node fill = r.take("fill");
  const bool fill_off =
      fill.IsDefined() && fill.IsScalar() && (fill.Scalar() == "none" || fill.Scalar() == "off");
  if (fill.IsDefined() && !fill.IsMap() && !fill_off)
    r.fail(fill, "fill", "expected 'none' or a map {style, angle, angle_step, overlap, ...}");
  s.fill.enabled = fill.IsDefined() && fill.IsMap();
  BlockReader fr(fill.IsMap() ? fill : YAML::Node(YAML::NodeType::Map), r.full_key("fill"),
                 std::make_shared<YamlSource>(r.source()));
  auto sub = [](const ParamSpec& p) {
    ParamSpec q = p;
    q.key = p.key.substr(5);  // "fill.angle" is "angle" inside the fill block
    return q;
  };
  static constexpr std::string_view kFillKeys[] = {"style",
                                                   "angle",
                                                   "angle_step",
                                                   "overlap",
                                                   "max_overlap",
                                                   "max_sparse_spacing",
                                                   "sparse_fill_gaps",
                                                   "boundary_overlap",
                                                   "boundary_side_overlap",
                                                   "max_end_overlap",
                                                   "max_side_overlap",
                                                   "optimize_to_surface",
                                                   "link_with_rapids",
                                                   "min_length",
                                                   "lead_in",
                                                   "lead_out",
                                                   "force_tangential_lead_out",
                                                   "fillet_radius",
                                                   "corner_melt_reduction",
                                                   "corner_speed",
                                                   "turns_outside",
                                                   "line_matching_limit",
                                                   "line_extension",
                                                   "step_tolerance",
                                                   "angle_tolerance"};
  slicer::FillParams& f = s.fill;
  {
    const std::string style = fr.string(sub(spec(t, "fill.style")));
    f.style = one_of(fr, "style", style, slicer::kFillStyles);
  }
  f.angle_deg = fr.quantity(sub(spec(t, "fill.angle")));
  f.angle_step_deg = fr.quantity(sub(spec(t, "fill.angle_step")));
  f.overlap = fr.quantity(sub(spec(t, "fill.overlap")));
  f.max_overlap = fr.quantity(sub(spec(t, "fill.max_overlap")));
  if (f.max_overlap < f.overlap)
    fr.fail(fr.take("max_overlap"), "max_overlap",
            fmt::format("maximum pass overlap {:.0f} % is below the pass overlap {:.0f} %",
                        100 * f.max_overlap, 100 * f.overlap));
  f.max_sparse_spacing_mm = fr.quantity(sub(spec(t, "fill.max_sparse_spacing")));
  f.sparse_fill_gaps = fr.boolean(sub(spec(t, "fill.sparse_fill_gaps")));
  f.boundary_overlap = fr.optional_quantity(sub(spec(t, "fill.boundary_overlap"))).value_or(f.overlap);
  f.boundary_side_overlap =
      fr.optional_quantity(sub(spec(t, "fill.boundary_side_overlap"))).value_or(f.overlap);
  f.max_end_overlap_mm = fr.quantity(sub(spec(t, "fill.max_end_overlap")));
  f.max_side_overlap_mm = fr.quantity(sub(spec(t, "fill.max_side_overlap")));
  f.optimize_to_surface = fr.boolean(sub(spec(t, "fill.optimize_to_surface")));
  f.link_with_rapids = fr.boolean(sub(spec(t, "fill.link_with_rapids")));
  f.min_length_mm = fr.quantity(sub(spec(t, "fill.min_length")));
  f.lead_in_mm = fr.quantity(sub(spec(t, "fill.lead_in")));
  f.lead_out_mm = fr.quantity(sub(spec(t, "fill.lead_out")));
  f.tangential_lead_out = fr.boolean(sub(spec(t, "fill.force_tangential_lead_out")));
  f.fillet_radius = fr.quantity(sub(spec(t, "fill.fillet_radius")));
  f.corner_melt_reduction = fr.quantity(sub(spec(t, "fill.corner_melt_reduction")));
  f.corner_speed_mm_s = fr.optional_quantity(sub(spec(t, "fill.corner_speed"))).value_or(0.0);
  f.turns_outside = fr.boolean(sub(spec(t, "fill.turns_outside")));
  f.line_matching_limit_mm = fr.quantity(sub(spec(t, "fill.line_matching_limit")));
  f.line_extension_mm = fr.quantity(sub(spec(t, "fill.line_extension")));
  f.step_tolerance_mm = fr.quantity(sub(spec(t, "fill.step_tolerance")));
  f.angle_tolerance_deg = fr.quantity(sub(spec(t, "fill.angle_tolerance")));
  fr.finish({}, kFillKeys);
  r.finish(t, std::array<std::string_view, 1>{"fill"});
  return s;
}

// Applies one `set` entry (dotted path = value) of a variant to the tree.
void apply_override(Tree& tree, const std::string& path, const YAML::Node& value, const SourceLocation& at) {
  std::vector<std::string> parts;
  {
    std::size_t start = 0;
    while (true) {
      const std::size_t dot = path.find('.', start);
      parts.push_back(path.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
      if (dot == std::string::npos) break;
      start = dot + 1;
    }
  }
  const std::string& head = parts.front();
  if (path == "program") {
    // The program a variant simulates (a baseline beside the program being checked).
    if (!tree.root["program"]) throw InputError(at, path, "the scenario simulates a part, not a program");
    tree.root["program"] = value;
    tree.overridden[path] = at;
    return;
  }
  YAML::Node target;
  std::size_t first = 1;
  if (head == "machine")
    target = tree.machine;
  else if (head == "material")
    target = tree.material;
  else if (head == "sections") {
    if (parts.size() < 3) throw InputError(at, path, "expected sections.<section name>.<key>");
    YAML::Node sections = tree.root["sections"];
    bool found = false;
    for (std::size_t i = 0; sections.IsSequence() && i < sections.size() && !found; ++i) {
      if (item_name(sections[i]) == parts[1]) {
        target.reset(sections[i]);
        found = true;
      }
    }
    if (!found) throw InputError(at, path, fmt::format("no section named '{}'", parts[1]));
    first = 2;
  } else if (head == "part" || head == "output" || head == "render" || head == "thermal" || head == "tools") {
    if (!tree.root[head]) tree.root[head] = YAML::Node(YAML::NodeType::Map);
    target.reset(tree.root[head]);
  } else {
    throw InputError(
        at, path,
        "a variant can set program, or keys under machine, material, part, output, render, thermal, tools "
        "or sections.<name>");
  }
  if (parts.size() <= first) throw InputError(at, path, "expected a key below the block");
  for (std::size_t i = first; i + 1 < parts.size(); ++i) {
    if (!target[parts[i]] || !target[parts[i]].IsMap()) target[parts[i]] = YAML::Node(YAML::NodeType::Map);
    YAML::Node next = target[parts[i]];
    target.reset(next);
  }
  target[parts.back()] = value;  // the same node, so messages keep its line in the scenario
  tree.overridden[path] = at;
}

Gate parse_gate(const YAML::Node& node, const std::string& file) {
  const SourceLocation at = location_of(node, file);
  if (!node.IsScalar()) throw InputError(at, "gates", "expected a gate such as 'porosity < 0.03'");
  return parse_gate_text(node.Scalar(), at);
}

}  // namespace

Gate parse_gate_text(const std::string& expr, const SourceLocation& at) {
  Gate g;
  g.expr = expr;
  g.where = at;
  static const std::pair<std::string_view, GateOp> kOps[] = {
      {"<=", GateOp::kLessEqual}, {">=", GateOp::kGreaterEqual}, {"==", GateOp::kEqual},
      {"!=", GateOp::kNotEqual},  {"<", GateOp::kLess},          {">", GateOp::kGreater}};
  std::size_t pos = std::string::npos, len = 0;
  for (const auto& [text, op] : kOps) {
    const std::size_t p = g.expr.find(text);
    if (p != std::string::npos) {
      pos = p;
      len = text.size();
      g.op = op;
      break;
    }
  }
  if (pos == std::string::npos)
    throw InputError(at, "gates", fmt::format("'{}' has no comparison (<, <=, >, >=, ==, !=)", g.expr));
  auto trim = [](std::string s) {
    s.erase(0, s.find_first_not_of(" \t"));
    s.erase(s.find_last_not_of(" \t") + 1);
    return s;
  };
  g.metric = trim(g.expr.substr(0, pos));
  const std::string rhs = trim(g.expr.substr(pos + len));
  if (!is_gate_metric(g.metric)) throw InputError(at, "gates", unknown_metric_message(g.metric));
  const auto number = [&](const std::string& text) {
    try {
      return parse_quantity(trim(text), Dimension::kFraction);
    } catch (const QuantityError& e) {
      throw InputError(
          at, "gates",
          fmt::format("'{}': the right-hand side must be a number, or baseline, baseline * number or "
                      "baseline + number: {}",
                      g.expr, e.what()));
    }
  };
  if (rhs.rfind("baseline", 0) == 0) {
    // Relative to the baseline variant: baseline, baseline * f, baseline + d, baseline - d.
    g.relative = true;
    const std::string rest = trim(rhs.substr(std::string_view("baseline").size()));
    if (!rest.empty()) {
      const char op = rest.front();
      const double v = number(rest.substr(1));
      if (op == '*')
        g.factor = v;
      else if (op == '+')
        g.offset = v;
      else if (op == '-')
        g.offset = -v;
      else
        throw InputError(at, "gates",
                         fmt::format("'{}': after baseline expected * number, + number or - number", g.expr));
    }
  } else {
    g.threshold = number(rhs);
  }
  return g;
}

namespace {

constexpr Colouring kColourings[] = {
    Colouring::kFusion,    Colouring::kSection,   Colouring::kLayer,
    Colouring::kTime,      Colouring::kSubstrate, Colouring::kHealing,
    Colouring::kDeviation, Colouring::kPorosity,  Colouring::kTemperature,
};
constexpr render::View kViews[] = {render::View::kIsometric, render::View::kTop, render::View::kFront,
                                   render::View::kSide, render::View::kUser};

// Three plain numbers [x, y, z], not all zero (a direction); the spec's default when absent.
Eigen::Vector3d read_direction(BlockReader& r, const ParamSpec& spec) {
  YAML::Node node = r.take(spec.key);
  const YAML::Node list = node.IsDefined() ? node : YAML::Load(std::string(spec.default_text));
  if (!list.IsSequence() || list.size() != 3) r.fail(node, spec.key, "expected three numbers [x, y, z]");
  Eigen::Vector3d d;
  for (std::size_t i = 0; i < 3; ++i)
    d[static_cast<Eigen::Index>(i)] = r.parse(list[i], Dimension::kDimensionless, std::string(spec.key));
  if (!(d.norm() > 0.0)) r.fail(node, spec.key, "a direction cannot be [0, 0, 0]");
  return d;
}

// The view and camera keys of an image or of the progress frames.
render::CameraSpec read_camera(BlockReader& r) {
  const auto t = image_params();
  render::CameraSpec c;
  c.view = one_of(r, "view", r.string(spec(t, "view")), kViews);
  c.field_of_view_deg = r.quantity(spec(t, "field_of_view"));
  if (c.field_of_view_deg > 0.0 && c.field_of_view_deg < 1.0)
    r.fail(r.take("field_of_view"), "field_of_view",
           fmt::format("must be 0 (orthographic) or 1..120 deg, got {:g} deg", c.field_of_view_deg));
  const bool user_keys = r.has("camera.position") || r.has("camera.target") || r.has("camera.direction");
  if (user_keys && c.view != render::View::kUser)
    r.fail(r.take("view"), "view", "the camera keys place a user camera: set view: user");
  if (r.has("camera.position")) c.position = read_vector(r, "camera.position", true).cast<float>();
  if (r.has("camera.target")) c.target = read_vector(r, "camera.target", true).cast<float>();
  c.direction = read_direction(r, spec(t, "camera.direction")).cast<float>();
  if (c.position && c.target && (*c.position - *c.target).norm() < 1e-3f)
    r.fail(r.take("camera.target"), "camera.target", "the eye is at the point it looks at: they must differ");
  return c;
}

// The unit a colouring's range is written in.
Dimension colouring_dimension(Colouring c) {
  switch (c) {
    case Colouring::kTime:
      return Dimension::kTime;
    case Colouring::kSubstrate:
    case Colouring::kTemperature:
      return Dimension::kTemperature;
    case Colouring::kHealing:
    case Colouring::kPorosity:
      return Dimension::kFraction;
    case Colouring::kDeviation:
      return Dimension::kLength;
    default:
      return Dimension::kDimensionless;
  }
}

ImageSpec read_image(BlockReader& r) {
  const auto t = image_params();
  ImageSpec im;
  const YAML::Node colour = r.take("colour");
  if (!colour.IsDefined() || !colour.IsScalar())
    r.fail(colour, "colour", "required: what colours the part (fusion, section, layer, ...)");
  im.colour = one_of(r, "colour", colour.Scalar(), kColourings);
  im.camera = read_camera(r);
  if (r.has("cut.point")) {
    CutSpec cut;
    cut.point = read_vector(r, "cut.point", true);
    cut.normal = read_direction(r, spec(t, "cut.normal")).normalized();
    im.cut = cut;
  } else if (r.has("cut.normal")) {
    r.fail(r.take("cut.normal"), "cut.normal", "a cut needs cut.point too");
  }
  if (r.has("layer")) im.up_to_layer = r.integer(spec(t, "layer"));
  if (r.has("time")) {
    if (im.colour != Colouring::kTemperature)
      r.fail(r.take("time"), "time", "only a picture coloured by temperature has a time");
    im.time_s = r.quantity(spec(t, "time"));
  }
  if (YAML::Node range = r.take("range"); range.IsDefined()) {
    if (im.colour == Colouring::kFusion || im.colour == Colouring::kSection)
      r.fail(range, "range", "fusion and section colour by category: they have no range");
    if (!range.IsSequence() || range.size() != 2) r.fail(range, "range", "expected [low, high]");
    const Dimension dim = colouring_dimension(im.colour);
    const double lo = r.parse(range[0], dim, "range"), hi = r.parse(range[1], dim, "range");
    if (!(lo < hi)) r.fail(range, "range", fmt::format("low ({:g}) must be below high ({:g})", lo, hi));
    im.range = std::pair{lo, hi};
  }
  const std::string view(render::to_string(im.camera.view));
  im.name = r.has("name") ? r.string(spec(t, "name"))
                          : std::string(to_string(im.colour)) + (view == "isometric" ? "" : "-" + view);
  if (im.name.empty() || im.name.find_first_of("/\\:*?\"<>|") != std::string::npos || im.name[0] == '.')
    r.fail(r.take("name"), "name", fmt::format("'{}' cannot be a file name", im.name));
  r.finish(t);
  return im;
}

// The pictures a scenario gets without a render.images list.
std::vector<ImageSpec> default_images() {
  std::vector<ImageSpec> out;
  const auto add = [&](Colouring c, render::View view, std::string name) {
    ImageSpec im;
    im.colour = c;
    im.camera.view = view;
    im.name = std::move(name);
    out.push_back(im);
  };
  add(Colouring::kFusion, render::View::kIsometric, "fusion");
  add(Colouring::kFusion, render::View::kTop, "fusion-top");
  add(Colouring::kSection, render::View::kIsometric, "sections");
  add(Colouring::kSubstrate, render::View::kIsometric, "substrate");
  add(Colouring::kDeviation, render::View::kIsometric, "deviation");
  return out;
}

RenderSpec read_render(BlockReader& r) {
  const auto t = render_params();
  RenderSpec rs;
  rs.width = r.integer(spec(t, "width"));
  rs.height = r.integer(spec(t, "height"));
  rs.samples = r.integer(spec(t, "samples"));
  rs.ambient_occlusion = r.boolean(spec(t, "ambient_occlusion"));
  rs.legend = r.boolean(spec(t, "legend"));
  rs.exr = r.boolean(spec(t, "exr"));
  rs.sheet = r.boolean(spec(t, "sheet"));
  if (YAML::Node images = r.take("images"); images.IsDefined()) {
    rs.images_given = true;
    if (!images.IsSequence())
      r.fail(images, "images", "expected a list of pictures such as [{colour: fusion, view: top}]");
    for (std::size_t i = 0; i < images.size(); ++i) {
      BlockReader ir(images[i], r.full_key(fmt::format("images[{}]", i)), r.shared_source(), r.overridden());
      if (!images[i].IsMap()) r.fail(images[i], "images", "each picture is a map {colour: ..., view: ...}");
      ImageSpec im = read_image(ir);
      for (const ImageSpec& other : rs.images)
        if (other.name == im.name)
          ir.fail(images[i], "name",
                  fmt::format("two pictures are named '{}': give one a name of its own", im.name));
      rs.images.push_back(std::move(im));
    }
  } else {
    rs.images = default_images();
  }
  if (YAML::Node progress = r.take("progress"); progress.IsDefined() && !progress.IsNull()) {
    if (progress.IsScalar() && progress.Scalar() == "none") {
    } else if (!progress.IsMap()) {
      r.fail(progress, "progress", "expected none or a map {colour: layer, view: isometric, every: 1}");
    } else {
      BlockReader pr(progress, r.full_key("progress"), r.shared_source(), r.overridden());
      ProgressSpec ps;
      const YAML::Node colour = pr.take("colour");
      ps.colour = colour.IsDefined() ? one_of(pr, "colour", colour.Scalar(), kColourings) : Colouring::kLayer;
      ps.camera = read_camera(pr);
      if (YAML::Node every = pr.take("every"); every.IsDefined()) {
        const long n = pr.whole_number(every.IsScalar() ? every.Scalar() : "", every, "every");
        if (n < 1 || n > 100000) pr.fail(every, "every", fmt::format("must be 1..100000, got {}", n));
        ps.every = static_cast<int>(n);
      }
      static constexpr std::string_view kKeys[] = {
          "colour", "every", "view", "field_of_view", "camera.position", "camera.target", "camera.direction"};
      pr.finish({}, kKeys);
      rs.progress = ps;
    }
  }
  r.finish(t);
  return rs;
}

Variant build_variant(const Tree& tree, const std::string& name, const std::filesystem::path& dir,
                      MeshCache& meshes) {
  Variant v;
  v.name = name;
  for (const auto* src : {tree.machine_src.get(), tree.material_src.get()})
    if (src != tree.scenario_src.get()) v.input_files.push_back(src->file);  // not an inline map
  BlockReader machine_r(tree.machine, "machine", tree.machine_src, &tree.overridden);
  v.machine = read_machine(machine_r);
  BlockReader material_r(tree.material, "material", tree.material_src, &tree.overridden);
  v.material = read_material(material_r);
  v.machine.extruder.max_flow_mm3_s = v.machine.extruder_max_output_kg_s / v.material.density_kg_m3 * 1e9;
  // The memory budget first: the part's mesh is read against it.
  BlockReader out_r(tree.root["output"], "output", tree.scenario_src, &tree.overridden);
  v.output.memory_budget_gb = out_r.quantity(spec(output_params(), "memory_budget"));
  BlockReader part_r(tree.root["part"], "part", tree.scenario_src, &tree.overridden);
  // No part is fine when every section prints an AM Outline (checked with the sections below).
  if (tree.root["part"])
    v.part = read_part(part_r, dir, meshes, v.output.memory_budget_gb * 1e9);
  else
    v.part.kind = PartSpec::Kind::kNone;
  if (v.part.kind == PartSpec::Kind::kMesh) v.input_files.push_back(v.part.mesh.string());

  v.output.voxel_size_mm = out_r.quantity(spec(output_params(), "voxel_size"));
  v.output.voxel_size_at = out_r.where(out_r.take("voxel_size"), "voxel_size");
  const std::string skin = out_r.string(spec(output_params(), "skin"));
  if (skin != "ply" && skin != "stl" && skin != "none")
    out_r.fail(out_r.take("skin"), "skin", fmt::format("expected ply, stl or none but found '{}'", skin));
  v.output.skin_format = skin == "none" ? "" : skin;
  v.output.skin_adaptivity = out_r.quantity(spec(output_params(), "skin_adaptivity"));
  v.output.skin_tolerance_mm = out_r.quantity(spec(output_params(), "skin_tolerance"));
  const std::string fields = out_r.string(spec(output_params(), "fields"));
  if (fields != "vtu" && fields != "none")
    out_r.fail(out_r.take("fields"), "fields", fmt::format("expected vtu or none but found '{}'", fields));
  v.output.write_fields = fields == "vtu";
  v.output.history_layers = read_integer_list(out_r, spec(output_params(), "history_layers"));
  out_r.finish(output_params());
  BlockReader render_r(tree.root["render"], "render", tree.scenario_src, &tree.overridden);
  v.render = read_render(render_r);

  BlockReader th_r(tree.root["thermal"], "thermal", tree.scenario_src, &tree.overridden);
  v.thermal.cells_across = th_r.integer(spec(thermal_params(), "cells_across"));
  if (v.thermal.cells_across % 2 == 0)
    th_r.fail(
        th_r.take("cells_across"), "cells_across",
        fmt::format("must be odd (a centre strip and edges on both sides), got {}", v.thermal.cells_across));
  v.thermal.cells_through = th_r.integer(spec(thermal_params(), "cells_through"));
  v.thermal.cell_length_mm = th_r.optional_quantity(spec(thermal_params(), "cell_length")).value_or(0.0);
  v.thermal.birth_interval_s = th_r.optional_quantity(spec(thermal_params(), "birth_interval")).value_or(0.0);
  if (YAML::Node snaps = th_r.take("snapshots"); snaps.IsDefined()) {
    const ParamSpec& s = spec(thermal_params(), "snapshots");
    if (!snaps.IsSequence())
      th_r.fail(snaps, "snapshots", "expected a list of times, such as [30 min, 1 h, end]");
    for (const YAML::Node& t : snaps) {
      if (t.IsScalar() && t.Scalar() == "end") {
        v.thermal.snapshot_times_s.push_back(std::numeric_limits<double>::infinity());
        continue;
      }
      const double value = th_r.parse(t, s.dim, "snapshots");
      th_r.check_range(s, value, t);
      v.thermal.snapshot_times_s.push_back(value);
    }
  }
  v.thermal.sample_interval_s = th_r.quantity(spec(thermal_params(), "sample_interval"));
  v.thermal.cooldown_s = th_r.quantity(spec(thermal_params(), "cooldown"));
  v.thermal.rel_tol = th_r.quantity(spec(thermal_params(), "rel_tol"));
  v.thermal.abs_tol_k = th_r.quantity(spec(thermal_params(), "abs_tol"));
  v.thermal.lump = th_r.boolean(spec(thermal_params(), "lump"));
  th_r.finish(thermal_params());

  // A print program instead of sections: read it with the machine's dialect.
  if (const YAML::Node prog = tree.root["program"]) {
    BlockReader pr(tree.root, "", tree.scenario_src, &tree.overridden);
    if (!prog.IsScalar() || prog.Scalar().empty())
      pr.fail(prog, "program", "expected the path of a G-code program");
    if (tree.root["sections"] || tree.root["part"])
      pr.fail(prog, "program", "a scenario simulates either a program or a part's sections, not both");
    v.program_file = dir / prog.Scalar();
    v.input_files.push_back(v.program_file.string());
    if (is_special_file(v.program_file))
      pr.fail(prog, "program", fmt::format("'{}' is not a regular file", v.program_file.string()));
    std::ifstream in(v.program_file, std::ios::binary);
    if (!in) pr.fail(prog, "program", fmt::format("cannot open '{}'", v.program_file.string()));
    slicer::ReadStats stats;
    const Extruder* extruder = v.machine.extruder.has_commands() ? &v.machine.extruder : nullptr;
    v.program = std::make_shared<const Toolpath>(
        slicer::read_gcode(in, v.program_file.string(), reader_options(v.machine, extruder), &stats));
    v.program_summary = fmt::format("{}: {} lines, {} layers, {} moves", v.program_file.filename().string(),
                                    stats.lines, v.program->layers.size(), v.program->moves.size());
    for (const std::string& w : stats.messages) meshes.warnings.push_back(w);
    v.part.kind = PartSpec::Kind::kNone;
    return v;
  }
  if (!v.part.loaded) v.part.loaded = std::make_shared<const slicer::TriangleMesh>(build_part_mesh(v.part));
  const std::map<std::string, Tool> tools = read_tools(tree, v.material);
  const YAML::Node sections = tree.root["sections"];
  if (!sections || !sections.IsSequence() || sections.size() == 0)
    throw InputError(location_of(sections ? sections : tree.root, tree.scenario_src->file), "sections",
                     "expected a list of sections, each with at least a name and z limits");
  for (std::size_t i = 0; i < sections.size(); ++i) {
    const std::optional<std::string> section_name = item_name(sections[i]);
    const std::string prefix = section_name ? "sections." + *section_name : fmt::format("sections[{}]", i);
    BlockReader sr(sections[i], prefix, tree.scenario_src, &tree.overridden);
    v.sections.push_back(read_section(sr, v.machine, v.material, *v.part.loaded, tools));
    if (v.part.kind == PartSpec::Kind::kNone && v.sections.back().outline_path.empty())
      throw InputError(
          location_of(sections[i], tree.scenario_src->file), prefix,
          "this section slices a part, but the scenario has no part: add part: {mesh: ...} (or give the "
          "section an outline to print)");
    for (std::size_t j = 0; j + 1 < v.sections.size(); ++j) {
      const auto& a = v.sections[j];
      const auto& b = v.sections.back();
      if (a.name == b.name)
        sr.fail(sections[i]["name"], "name", fmt::format("a section named '{}' already exists", b.name));
      const bool other_bodies = !a.body.empty() && !b.body.empty() && a.body != b.body;
      if (!other_bodies && b.z_min_mm < a.z_max_mm - 1e-9 && a.z_min_mm < b.z_max_mm - 1e-9)
        sr.fail(
            sections[i]["z"], "z",
            fmt::format("overlaps section '{}' in Z ({} to {} mm); sections may share heights only when they "
                        "slice different bodies",
                        a.name, a.z_min_mm, a.z_max_mm));
    }
  }
  // A shared wall (patent (17)) is checked here too, where the message can point at the key.
  for (std::size_t i = 0; i < v.sections.size(); ++i) {
    const slicer::SectionParams& b = v.sections[i];
    if (b.shares_wall_with.empty()) continue;
    const std::string prefix = "sections." + b.name;
    BlockReader sr(sections[i], prefix, tree.scenario_src, &tree.overridden);
    if (const std::string problem = slicer::shared_wall_problem(v.sections, b); !problem.empty())
      sr.fail(sections[i]["shares_wall_with"], "shares_wall_with", problem);
  }
  return v;
}

}  // namespace

std::string_view to_string(Colouring colouring) {
  switch (colouring) {
    case Colouring::kFusion:
      return "fusion";
    case Colouring::kSection:
      return "section";
    case Colouring::kLayer:
      return "layer";
    case Colouring::kTime:
      return "time";
    case Colouring::kSubstrate:
      return "substrate";
    case Colouring::kHealing:
      return "healing";
    case Colouring::kDeviation:
      return "deviation";
    case Colouring::kPorosity:
      return "porosity";
    case Colouring::kTemperature:
      return "temperature";
  }
  return "?";
}

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

namespace {

// Parses the scenario text and the machine and material it names. Called once per variant: each variant
// gets its own tree to override, and a fresh parse (unlike YAML::Clone) keeps every node's line and column.
Tree parse_tree(const std::string& text, const std::string& file, const std::filesystem::path& dir) {
  Tree tree;
  tree.root = parse_yaml(text, file);
  if (!tree.root.IsMap())
    throw InputError(
        {file, 1, 1}, {},
        "a scenario must be a map of keys and values (name, machine, material, part, sections...)");
  tree.scenario_src = std::make_shared<YamlSource>();
  tree.scenario_src->file = file;
  tree.scenario_src->default_units = read_units_block(tree.root["units"], file);
  tree.machine = resolve_library(tree.root, "machine", tree.scenario_src, dir, tree.machine_src);
  tree.material = resolve_library(tree.root, "material", tree.scenario_src, dir, tree.material_src);
  return tree;
}

}  // namespace

std::set<std::string> input_files(const Scenario& sc) {
  std::set<std::string> files;
  for (const Variant& v : sc.variants) files.insert(v.input_files.begin(), v.input_files.end());
  return files;
}

std::string contents_digest(const std::set<std::string>& files) {
  Fnv1a h;
  const std::string_view end("\0", 1);
  const auto& shipped = shipped_files();
  for (const std::string& file : files) {
    h.add(file).add(end);
    if (file.starts_with(kBuiltIn)) {
      const auto it = shipped.find(file.substr(kBuiltIn.size() + 1));
      if (it != shipped.end()) h.add(it->second);
    } else if (std::ifstream in(file, std::ios::binary); in) {
      std::string chunk(1 << 20, '\0');
      while (in.read(chunk.data(), static_cast<std::streamsize>(chunk.size())) || in.gcount() > 0)
        h.add(std::string_view(chunk.data(), static_cast<std::size_t>(in.gcount())));
    }
    h.add(end);
  }
  return h.hex();
}

Setting parse_setting(const std::string& text) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError(
        {"command line", 0, 0}, "--set",
        fmt::format("expected KEY=VALUE (such as sections.walls.speed=1.2in/s), got '{}'", text));
  std::string key = text.substr(0, eq);
  key.erase(key.find_last_not_of(" \t") + 1);
  return {key, text.substr(eq + 1)};
}

namespace {

Scenario build_scenario(const std::string& text, const std::string& file,
                        const std::vector<Setting>& settings) {
  // Beside the scenario file ("." for one named without a directory); none for a built-in one.
  std::filesystem::path dir;
  if (!file.empty() && !file.starts_with(kBuiltIn)) {
    dir = std::filesystem::path(file).parent_path();
    if (dir.empty()) dir = ".";
  }
  const Tree base = parse_tree(text, file, dir);
  const YAML::Node& root = base.root;

  Scenario sc;
  sc.file = file;
  if (const auto unit = base.scenario_src->default_units.find(Dimension::kLength);
      unit != base.scenario_src->default_units.end())
    sc.inches = unit->second == "in" || unit->second == "inch" || unit->second == "inches";
  {
    BlockReader top(root, "", base.scenario_src);
    static const ParamSpec kName{
        "name", ParamType::kString, Dimension::kDimensionless, "", 0, 0, false, "scenario name", ""};
    static const ParamSpec kDesc{
        "description", ParamType::kString, Dimension::kDimensionless, "-", 0, 0, false, "", ""};
    sc.name = top.string(kName);
    sc.description = top.string(kDesc);
    static constexpr std::string_view kKeys[] = {"units",    "machine",  "material", "part",
                                                 "output",   "render",   "thermal",  "tools",
                                                 "sections", "variants", "gates",    "program"};
    for (const auto k : kKeys) (void)top.take(k);
    static const ParamSpec kTop[] = {kName, kDesc};
    top.finish(kTop, kKeys);
  }
  if (const YAML::Node gates = root["gates"]) {
    if (!gates.IsSequence())
      throw InputError(location_of(gates, file), "gates",
                       "expected a list of gates such as '- porosity < 0.03'");
    for (const auto& g : gates) sc.gates.push_back(parse_gate(g, file));
  }

  // Variants: each its own tree with its overrides applied; no variants means one called "baseline".
  std::vector<std::pair<std::string, YAML::Node>> variant_nodes;
  if (const YAML::Node vars = root["variants"]) {
    if (!vars.IsSequence() || vars.size() == 0)
      throw InputError(location_of(vars, file), "variants",
                       "expected a list of variants, each with a name and optionally set: {key: value}");
    for (const auto& vn : vars) {
      if (!vn.IsMap() || !vn["name"] || !vn["name"].IsScalar())
        throw InputError(location_of(vn, file), "variants", "each variant needs a name");
      for (auto it = vn.begin(); it != vn.end(); ++it)
        if (it->first.Scalar() != "name" && it->first.Scalar() != "set")
          throw InputError(location_of(it->first, file),
                           "variants." + vn["name"].Scalar() + "." + it->first.Scalar(),
                           "unknown key; expected name or set");
      for (const auto& [n, _] : variant_nodes)
        if (n == vn["name"].Scalar())
          throw InputError(location_of(vn["name"], file), "variants",
                           fmt::format("a variant named '{}' already exists", n));
      variant_nodes.emplace_back(vn["name"].Scalar(), vn["set"]);
    }
  } else {
    variant_nodes.emplace_back("baseline", YAML::Node());
  }
  MeshCache meshes;
  for (const auto& [name, set] : variant_nodes) {
    Tree tree = variant_nodes.size() == 1 ? base : parse_tree(text, file, dir);
    std::map<std::string, std::string> overrides;
    if (set.IsDefined() && !set.IsNull()) {
      if (!set.IsMap())
        throw InputError(location_of(set, file), "variants." + name + ".set",
                         "expected a map {key.path: value}");
      for (auto it = set.begin(); it != set.end(); ++it) {
        const std::string path = it->first.Scalar();
        apply_override(tree, path, it->second, location_of(it->second, file));
        overrides[path] = it->second.IsScalar() ? it->second.Scalar() : YAML::Dump(it->second);
      }
    }
    for (const Setting& setting : settings) {
      const SourceLocation at{"command line (--set " + setting.key + "=" + setting.value + ")", 0, 0};
      YAML::Node value;
      try {
        value = YAML::Load(setting.value);
      } catch (const YAML::Exception& e) {
        throw InputError(at, setting.key, fmt::format("the value is not YAML: {}", e.msg));
      }
      apply_override(tree, setting.key, value, at);
      overrides[setting.key] = setting.value;
    }
    Variant v = build_variant(tree, name, dir, meshes);
    v.overrides = std::move(overrides);
    sc.variants.push_back(std::move(v));
  }
  sc.warnings = std::move(meshes.warnings);
  return sc;
}

}  // namespace

Scenario load_scenario_text(const std::string& text, const std::string& file,
                            const std::vector<Setting>& settings) {
  try {
    return build_scenario(text, file, settings);
  } catch (const YAML::Exception& e) {
    // Nodes are checked for their kind before they are read, with messages naming the key; yaml-cpp's own
    // error (a map asked of a scalar, a value of the wrong type) is the last line of defence, at its mark.
    throw InputError({file, e.mark.line + 1, e.mark.column + 1}, {},
                     fmt::format("unexpected YAML structure: {}", e.msg));
  }
}

Scenario load_scenario(const std::filesystem::path& path, const std::vector<Setting>& settings) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError({path.string(), 0, 0}, {},
                     std::filesystem::exists(path, ec) ? "not a regular file" : "no such scenario file");
  return load_scenario_text(read_text_file(path, {path.string(), 0, 0}, {}), path.string(), settings);
}

std::vector<Gate> load_gates(const std::filesystem::path& path) {
  const std::string file = path.string();
  const YAML::Node root = parse_yaml(read_text_file(path, {file, 0, 0}, "--gates"), file);
  const YAML::Node list = root.IsMap() ? root["gates"] : root;
  if (!list || !list.IsSequence())
    throw InputError(location_of(root, file), "gates",
                     "expected a list of gates such as '- porosity < 0.03' (or a scenario with gates:)");
  std::vector<Gate> out;
  for (const YAML::Node& g : list) out.push_back(parse_gate(g, file));
  return out;
}

Scenario load_default_scenario(const std::vector<Setting>& settings) {
  const auto& files = shipped_files();
  const auto it = files.find("default.yaml");
  if (it == files.end()) throw InternalError("the default scenario is not embedded");
  return load_scenario_text(it->second, std::string(kBuiltIn) + "/default.yaml", settings);
}

}  // namespace beadtwin::scenarios

namespace beadtwin::scenarios {

namespace {

// The program a check reads, open for the guesses made from its text before it is read.
std::ifstream open_program(const std::filesystem::path& program) {
  if (is_special_file(program)) throw InputError({program.string(), 0, 0}, "program", "not a regular file");
  std::ifstream in(program, std::ios::binary);
  if (!in) throw InputError({program.string(), 0, 0}, "program", "cannot open the program");
  return in;
}

}  // namespace

std::string infer_machine(const std::filesystem::path& program, std::string* why) {
  std::ifstream in = open_program(program);
  std::string text(std::size_t{1} << 20, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  std::istringstream lines(text);
  int e_words = 0, melt_codes = 0;
  for (std::string line; std::getline(lines, line);) {
    const std::string code = line.substr(0, line.find_first_of(";("));
    if ((code.rfind("G1", 0) == 0 || code.rfind("G0", 0) == 0) && code.find(" E") != std::string::npos)
      ++e_words;
    if (code.rfind("M23", 0) == 0 || code.rfind("M24", 0) == 0) ++melt_codes;
  }
  if (e_words > melt_codes) {
    if (why) *why = fmt::format("{} moves with E words: a filament printer", e_words);
    return "desktop-fff";
  }
  if (why)
    *why = melt_codes > 0 ? fmt::format("{} M23/M24 melt codes and no E words: a pellet gantry", melt_codes)
                          : std::string("no E words: a pellet gantry");
  return "lsam-ph15";
}

std::string stated_filament_type(const std::filesystem::path& program) {
  std::ifstream in = open_program(program);
  std::string type = slicer::stated_setting(in, "filament_type").value_or("");
  type = type.substr(0, type.find(';'));  // several extruders: "PLA;PETG", the first taken
  while (!type.empty() && type.back() == ' ') type.pop_back();
  return type;
}

Scenario load_program_check(const ProgramCheck& check) {
  std::vector<std::string> assumed;
  YAML::Node doc(YAML::NodeType::Map);
  std::string file = "<check>";
  if (!check.scenario.empty()) {
    // Machine, material, units, output, render, thermal and gates from the scenario; its part and sections
    // are not used.
    file = check.scenario.string();
    const std::string text = read_text_file(check.scenario, {file, 0, 0}, {});
    YAML::Node base;
    try {
      base = YAML::Load(text);
    } catch (const YAML::Exception& e) {
      throw InputError({file, e.mark.line + 1, e.mark.column + 1}, {}, e.msg);
    }
    for (const char* key : {"units", "machine", "material", "output", "render", "thermal", "gates"})
      if (base[key]) doc[key] = base[key];
  }
  doc["name"] = "check " + check.program.filename().string();
  if (!doc["units"]) doc["units"] = YAML::Load("{length: mm}");
  if (!check.machine.empty()) {
    doc["machine"] = check.machine;
  } else if (!doc["machine"]) {
    std::string why;
    doc["machine"] = infer_machine(check.program, &why);
    assumed.push_back(
        fmt::format("assumed machine {} ({}); give --machine to choose", doc["machine"].Scalar(), why));
  }
  if (!check.material.empty()) {
    doc["material"] = check.material;
  } else if (!doc["material"]) {
    // The filament a desktop slicer says it sliced for, where the shipped library has a material of that
    // name; else the shipped CF-ABS.
    const std::string type = stated_filament_type(check.program);
    std::string lower = type;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (!lower.empty() && shipped_files().contains("materials/" + lower + ".yaml")) {
      doc["material"] = lower;
      assumed.push_back(
          fmt::format("assumed material {} (the program says filament_type = {}); give --material to choose",
                      lower, type));
    } else {
      doc["material"] = "cf-abs-20";
      assumed.push_back(
          type.empty() ? std::string("assumed material cf-abs-20 (the shipped material); give --material to "
                                     "choose")
                       : fmt::format("assumed material cf-abs-20 (the shipped material): the program's "
                                     "filament_type {} is not one beadtwin ships; give --material to choose",
                                     type));
    }
  }
  doc["program"] = std::filesystem::absolute(check.program).string();
  YAML::Node variants(YAML::NodeType::Sequence);
  YAML::Node program_variant(YAML::NodeType::Map);
  program_variant["name"] = "program";
  variants.push_back(program_variant);
  if (!check.baseline.empty()) {
    YAML::Node baseline(YAML::NodeType::Map);
    baseline["name"] = "baseline";
    baseline["set"]["program"] = std::filesystem::absolute(check.baseline).string();
    variants.push_back(baseline);
  }
  doc["variants"] = variants;
  YAML::Emitter out;
  out << doc;
  Scenario sc = load_scenario_text(out.c_str(), file, check.settings);
  sc.warnings.insert(sc.warnings.begin(), assumed.begin(), assumed.end());
  return sc;
}

}  // namespace beadtwin::scenarios

namespace beadtwin::scenarios {

void check_gate_sections(const Scenario& sc) {
  // A program's sections are known once it is read: its gates are judged then.
  for (const Variant& v : sc.variants)
    if (v.program) return;
  for (const Gate& g : sc.gates) {
    const std::optional<std::string> section = gate_metric_section(g.metric);
    if (!section) continue;
    std::vector<std::string> names;
    for (const Variant& v : sc.variants)
      for (const slicer::SectionParams& s : v.sections)
        if (std::find(names.begin(), names.end(), s.name) == names.end()) names.push_back(s.name);
    if (std::find(names.begin(), names.end(), *section) != names.end()) continue;
    throw InputError(g.where, "gates",
                     fmt::format("'{}' names section '{}', which no variant has; the sections are: {}",
                                 g.expr, *section, fmt::join(names, ", ")));
  }
}

}  // namespace beadtwin::scenarios
