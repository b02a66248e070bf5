#include "scenarios/input/scenario.hpp"

#include <algorithm>
#include <fstream>

#include <fmt/format.h>

#include "core/hash.hpp"
#include "gcode/program_reader.hpp"
#include "gcode/reader_options.hpp"
#include "scenarios/input/embedded.hpp"
#include "scenarios/input/params.hpp"
#include "scenarios/input/scenario_blocks.hpp"
#include "scenarios/input/yaml_reader.hpp"

namespace beadtwin::scenarios {
namespace {

constexpr std::string_view kBuiltIn = "<built-in>";

// A list item's name: its `name` when it is a map with a scalar one. yaml-cpp throws when a scalar or a list
// is asked for a key, so an item that is not a map must not be asked.
std::optional<std::string> item_name(const YAML::Node& item) {
  if (!item.IsMap()) return std::nullopt;
  const YAML::Node name = item["name"];
  if (!name || !name.IsScalar()) return std::nullopt;
  return name.Scalar();
}

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
gcode::ReaderOptions reader_options(const Machine& m, const Extruder* extruder) {
  gcode::ReaderOptions o = gcode::reader_options_for(m.dialect, extruder);
  o.max_macro_steps = m.macro_step_limit;
  o.roller_down_at_start = m.flattens() && m.dialect.roller_down.empty();
  return o;
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

// A print program instead of sections (`program:`), read with the machine's dialect.
void read_program(const Tree& tree, const std::filesystem::path& dir, Variant& v, MeshCache& meshes) {
  const YAML::Node prog = tree.root["program"];
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
  gcode::ReadStats stats;
  const Extruder* extruder = v.machine.extruder.has_commands() ? &v.machine.extruder : nullptr;
  v.program = std::make_shared<const Toolpath>(
      gcode::read_gcode(in, v.program_file.string(), reader_options(v.machine, extruder), &stats));
  v.program_summary = fmt::format("{}: {} lines, {} layers, {} moves", v.program_file.filename().string(),
                                  stats.lines, v.program->layers.size(), v.program->moves.size());
  for (const std::string& w : stats.messages) meshes.warnings.push_back(w);
  v.part.kind = PartSpec::Kind::kNone;
}

// The sections, each read against the part and the tools, and what they must agree on among themselves:
// unique names, no overlap in Z (unless they slice different bodies), a shared wall that exists.
void read_sections(const Tree& tree, Variant& v) {
  const std::map<std::string, Tool> tools =
      read_tools(tree.root["tools"], tree.scenario_src, &tree.overridden, v.material);
  const YAML::Node sections = tree.root["sections"];
  if (!sections || !sections.IsSequence() || sections.size() == 0)
    throw InputError(location_of(sections ? sections : tree.root, tree.scenario_src->file), "sections",
                     "expected a list of sections, each with at least a name and z limits");
  const SectionContext context{v.machine, v.material, *v.part.loaded, tools};
  for (std::size_t i = 0; i < sections.size(); ++i) {
    const std::optional<std::string> section_name = item_name(sections[i]);
    const std::string prefix = section_name ? "sections." + *section_name : fmt::format("sections[{}]", i);
    BlockReader sr(sections[i], prefix, tree.scenario_src, &tree.overridden);
    v.sections.push_back(read_section(sr, context));
    const slicer::SectionParams& b = v.sections.back();
    if (v.part.kind == PartSpec::Kind::kNone && b.outline_path.empty())
      throw InputError(
          location_of(sections[i], tree.scenario_src->file), prefix,
          "this section slices a part, but the scenario has no part: add part: {mesh: ...} (or give the "
          "section an outline to print)");
    for (std::size_t j = 0; j + 1 < v.sections.size(); ++j) {
      const slicer::SectionParams& a = v.sections[j];
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
    BlockReader sr(sections[i], "sections." + b.name, tree.scenario_src, &tree.overridden);
    if (const std::string problem = slicer::shared_wall_problem(v.sections, b); !problem.empty())
      sr.fail(sections[i]["shares_wall_with"], "shares_wall_with", problem);
  }
}

// One variant from its tree (the scenario with the variant's settings applied): machine, material, output
// (its memory budget first: the part's mesh is read against it), part, pictures, thermal settings, and a
// program or sections.
Variant build_variant(const Tree& tree, const std::string& name, const std::filesystem::path& dir,
                      MeshCache& meshes) {
  Variant v;
  v.name = name;
  for (const auto* src : {tree.machine_src.get(), tree.material_src.get()})
    if (src != tree.scenario_src.get()) v.input_files.push_back(src->file);  // not an inline map
  const auto block = [&](const YAML::Node& node, const char* prefix, const std::shared_ptr<YamlSource>& src) {
    return BlockReader(node, prefix, src, &tree.overridden);
  };
  BlockReader machine_r = block(tree.machine, "machine", tree.machine_src);
  v.machine = read_machine(machine_r);
  BlockReader material_r = block(tree.material, "material", tree.material_src);
  v.material = read_material(material_r);
  v.machine.extruder.max_flow_mm3_s = v.machine.extruder_max_output_kg_s / v.material.density_kg_m3 * 1e9;
  BlockReader output_r = block(tree.root["output"], "output", tree.scenario_src);
  v.output = read_output(output_r);
  // No part is fine when every section prints an AM Outline (checked with the sections).
  v.part.kind = PartSpec::Kind::kNone;
  if (tree.root["part"]) {
    BlockReader part_r = block(tree.root["part"], "part", tree.scenario_src);
    v.part = read_part(part_r, dir, meshes, v.output.memory_budget_gb * 1e9);
  }
  if (v.part.kind == PartSpec::Kind::kMesh) v.input_files.push_back(v.part.mesh.string());
  BlockReader render_r = block(tree.root["render"], "render", tree.scenario_src);
  v.render = read_render(render_r);
  BlockReader thermal_r = block(tree.root["thermal"], "thermal", tree.scenario_src);
  v.thermal = read_thermal(thermal_r);
  if (tree.root["program"]) {
    read_program(tree, dir, v, meshes);
    return v;
  }
  if (!v.part.loaded) v.part.loaded = std::make_shared<const slicer::TriangleMesh>();
  read_sections(tree, v);
  return v;
}

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

// The top level's own keys (name, description) and the blocks it holds, each read by its own reader.
void read_top_level(const Tree& base, Scenario& sc) {
  BlockReader top(base.root, "", base.scenario_src);
  top.read(scenario_params(), sc);
  for (const Param<Scenario>& p : scenario_params()) (void)top.take(p.key);
  top.finish(scenario_params());
  if (const YAML::Node gates = base.root["gates"]) sc.gates = read_gates(gates, sc.file);
}

// The variants' names and settings: each {name, set}; none means one called "baseline".
std::vector<std::pair<std::string, YAML::Node>> variant_list(const YAML::Node& root,
                                                             const std::string& file) {
  std::vector<std::pair<std::string, YAML::Node>> out;
  const YAML::Node vars = root["variants"];
  if (!vars) return {{"baseline", YAML::Node()}};
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
    for (const auto& [n, _] : out)
      if (n == vn["name"].Scalar())
        throw InputError(location_of(vn["name"], file), "variants",
                         fmt::format("a variant named '{}' already exists", n));
    out.emplace_back(vn["name"].Scalar(), vn["set"]);
  }
  return out;
}

// A variant's settings and the command line's, applied to its tree; returns them as written, for the report.
std::map<std::string, std::string> apply_settings(Tree& tree, const std::string& name, const YAML::Node& set,
                                                  const std::vector<Setting>& settings,
                                                  const std::string& file) {
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
  return overrides;
}

Scenario build_scenario(const std::string& text, const std::string& file,
                        const std::vector<Setting>& settings) {
  // Beside the scenario file ("." for one named without a directory); none for a built-in one.
  std::filesystem::path dir;
  if (!file.empty() && !file.starts_with(kBuiltIn)) {
    dir = std::filesystem::path(file).parent_path();
    if (dir.empty()) dir = ".";
  }
  const Tree base = parse_tree(text, file, dir);
  Scenario sc;
  sc.file = file;
  if (const auto unit = base.scenario_src->default_units.find(Dimension::kLength);
      unit != base.scenario_src->default_units.end())
    sc.inches = unit->second == "in" || unit->second == "inch" || unit->second == "inches";
  read_top_level(base, sc);
  // Each variant its own tree with its settings applied.
  const std::vector<std::pair<std::string, YAML::Node>> variants = variant_list(base.root, file);
  MeshCache meshes;
  for (const auto& [name, set] : variants) {
    Tree tree = variants.size() == 1 ? base : parse_tree(text, file, dir);
    std::map<std::string, std::string> overrides = apply_settings(tree, name, set, settings, file);
    Variant v = build_variant(tree, name, dir, meshes);
    v.overrides = std::move(overrides);
    sc.variants.push_back(std::move(v));
  }
  sc.warnings = std::move(meshes.warnings);
  return sc;
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

Scenario load_default_scenario(const std::vector<Setting>& settings) {
  const auto& files = shipped_files();
  const auto it = files.find("default.yaml");
  if (it == files.end()) throw InternalError("the default scenario is not embedded");
  return load_scenario_text(it->second, std::string(kBuiltIn) + "/default.yaml", settings);
}

}  // namespace beadtwin::scenarios
