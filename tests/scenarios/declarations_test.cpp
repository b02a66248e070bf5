// The parameter declarations (core/param.hpp; scenarios/input/params.hpp, slicer/section_params.hpp) held
// against the code that uses them: every declared key is read into the member it names, every default is
// the struct's own, every range is enforced at its key, and every machine code a scenario sets reaches the
// program writer and reader.
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>

#include "core/flow.hpp"
#include "core/melt_settings.hpp"
#include "gcode/program_reader.hpp"
#include "gcode/reader_options.hpp"
#include "gcode/writer.hpp"
#include "scenarios/input/params.hpp"
#include "scenarios/input/yaml_reader.hpp"
#include "slicer/section_params.hpp"

namespace beadtwin::scenarios {
namespace {

// The scenario every key is tried in: inline machine and material (so no file's units apply), two sections
// (one with fill), a tool, and an image.
const std::string kBase = R"(name: declarations
machine: {name: m, gcode: {melt_on: M23, melt_off: M24}}
material:
  name: x
  density: 1140
  specific_heat: 1640
  conductivity: {along: 0.2, across: 0.2, through: 0.2}
  emissivity: 0.9
  deposition_temp: 200 C
  glass_transition: 110 C
  fusion: {viscosity: 1e5 Pa*s, healing_ref_temp: 200 C, reptation_time: 1 s, activation_energy: 150 kJ/mol,
           min_healing_temp: 110 C, required_healing: 0.9}
part:
  open_box: {size: [240 mm, 180 mm, 30 mm], wall: 40 mm, floor: 10 mm}
tools: {t: {bead_width: 20 mm, bead_thickness: 5 mm}}
render: {images: [{colour: layer}]}
sections:
  - {name: floor, z: [0 mm, 10 mm], layer_height: 5 mm, bead_width: 20 mm, fill: {angle: 45 deg}}
  - {name: walls, z: [10 mm, 30 mm], layer_height: 5 mm, bead_width: 20 mm, fill: none}
)";

// A value as a file writes it, with the internal unit of `dim` on each number (of `column_dim` on the
// first of a table's two columns).
std::string yaml_text(const ParamValue& v, Dimension dim, Dimension column_dim = Dimension::kDimensionless,
                      bool table = false) {
  if (const double* d = std::get_if<double>(&v.value)) {
    const std::string_view unit = internal_unit(dim);
    return unit.empty() ? fmt::format("{}", *d) : fmt::format("{} {}", *d, unit);
  }
  if (const long* l = std::get_if<long>(&v.value)) return fmt::format("{}", *l);
  if (const bool* b = std::get_if<bool>(&v.value)) return *b ? "true" : "false";
  if (const std::string* s = std::get_if<std::string>(&v.value)) return *s;
  std::string out = "[";
  const ParamValue::List& list = v.list();
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (table)
      out += fmt::format("{}[{}, {}]", i ? ", " : "", yaml_text(list[i].list().at(0), column_dim),
                         yaml_text(list[i].list().at(1), dim));
    else
      out += (i ? ", " : "") + yaml_text(list[i], dim);
  }
  return out + "]";
}

// A value within the declared range that differs from the default, of the member's shape.
ParamValue sample(const ParamInfo& p, ParamShape shape, std::size_t point_size,
                  const std::vector<std::string_view>& spellings, const ParamValue& current) {
  const ParamRange& r = p.range;
  const auto number = [&](bool whole) -> double {
    double v = 1.5;
    if (!std::isinf(r.min) && !std::isinf(r.max))
      v = r.min + 0.375 * (r.max - r.min);
    else if (!std::isinf(r.min))
      v = r.min + 1.5;
    else if (!std::isinf(r.max))
      v = r.max - 1.5;
    return whole ? std::ceil(v) : v;
  };
  switch (shape) {
    case ParamShape::kNumber:
      return number(false);
    case ParamShape::kInteger:
      return static_cast<long>(number(true));
    case ParamShape::kFlag:
      if (!spellings.empty()) return std::string(spellings[current.text() == spellings[0] ? 1 : 0]);
      return !current.flag();
    case ParamShape::kText:
    case ParamShape::kChoice:
      for (const std::string_view s : spellings)
        if (current.empty() || std::get_if<std::string>(&current.value) == nullptr || s != current.text())
          return std::string(s);
      return std::string("M901");
    case ParamShape::kPoint: {
      ParamValue::List out;
      for (std::size_t i = 0; i < point_size; ++i) out.emplace_back(number(false) + static_cast<double>(i));
      return out;
    }
    case ParamShape::kPolygon:
    case ParamShape::kPolygons: {
      ParamValue::List square;
      for (const auto& [x, y] : {std::pair{10.0, 10.0}, {60.0, 10.0}, {60.0, 50.0}, {10.0, 50.0}})
        square.emplace_back(ParamValue::List{x, y});
      return shape == ParamShape::kPolygon ? ParamValue(square) : ParamValue(ParamValue::List{square});
    }
    case ParamShape::kTable:
      return ParamValue::List{ParamValue::List{1.0, number(false)}, ParamValue::List{2.0, number(false)}};
    case ParamShape::kIntegers:
      return ParamValue::List{1L, 2L};
    case ParamShape::kNone:
      break;
  }
  return {};
}

// Two values agree: equal, or numbers within a part in 10^12 (a unit's factor applied in another order), or
// polygons that are the same up to which point they start at (the union the loader makes of them).
bool agree(const ParamValue& a, const ParamValue& b);

bool same_polygon(const ParamValue::List& a, const ParamValue::List& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t shift = 0; shift < a.size(); ++shift) {
    bool all = true;
    for (std::size_t i = 0; i < a.size() && all; ++i) all = agree(a[i], b[(i + shift) % b.size()]);
    if (all) return true;
  }
  return false;
}

bool agree(const ParamValue& a, const ParamValue& b) {
  if (std::holds_alternative<double>(a.value) || std::holds_alternative<double>(b.value)) {
    if (a.empty() || b.empty() || std::holds_alternative<ParamValue::List>(a.value)) return a == b;
    const double x = a.number(), y = b.number();
    return std::abs(x - y) <= 1e-12 * std::max({1.0, std::abs(x), std::abs(y)});
  }
  if (const auto* la = std::get_if<ParamValue::List>(&a.value)) {
    const auto* lb = std::get_if<ParamValue::List>(&b.value);
    if (!lb || la->size() != lb->size()) return false;
    bool all = true;
    for (std::size_t i = 0; i < la->size() && all; ++i) all = agree((*la)[i], (*lb)[i]);
    return all || same_polygon(*la, *lb);
  }
  return a == b;
}

std::string shown(const ParamValue& v) {
  return v.empty() ? std::string("nothing") : yaml_text(v, Dimension::kDimensionless);
}

// A block as its struct starts: its members' initialisers.
template <class B>
B starting() {
  B b;
  return b;
}

// How each block of the scenario is set from the command line, read back from the loaded scenario, and
// what else a sample needs to stand (the keys beside it that the loader checks it against).
template <class B>
struct Block {
  std::string title;
  std::span<const Param<B>> params;
  std::function<std::string(std::string_view key)> path;  // --set KEY for a declared key
  std::function<const B*(const Scenario&)> loaded;        // null: the block is not kept in the scenario
  std::map<std::string_view, std::vector<Setting>> companions = {};
  std::map<std::string_view, std::string> samples = {};  // where a valid value depends on the scenario
  std::set<std::string_view> refused = {};               // shown read by a wrong value refused at the key
};

Scenario load_with(const std::vector<Setting>& settings, const std::string& part = {}) {
  std::string text = kBase;
  if (!part.empty()) {
    const std::size_t at = text.find("part:\n"), end = text.find("tools:");
    text.replace(at, end - at, "part: " + part + "\n");
  }
  return load_scenario_text(text, "declarations.yaml", settings);
}

template <class B>
void every_key_is_read_into_its_member(const Block<B>& block) {
  const B defaults = starting<B>();
  for (const Param<B>& p : block.params) {
    if (!p.member) continue;
    const std::vector<std::string_view> spellings = p.spellings();
    const auto given = block.samples.find(p.key);
    const ParamValue value = given != block.samples.end()
                                 ? ParamValue(given->second)
                                 : sample(p, p.shape(), p.member.point_size(), spellings, p.get(defaults));
    std::vector<Setting> settings = {
        {block.path(p.key), yaml_text(value, p.dim, p.column_dim, p.shape() == ParamShape::kTable)}};
    if (const auto it = block.companions.find(p.key); it != block.companions.end())
      settings.insert(settings.end(), it->second.begin(), it->second.end());
    const std::string what = fmt::format("{} {} = {}", block.title, p.key, settings.front().value);
    if (block.refused.contains(p.key)) {
      try {
        (void)load_with({{block.path(p.key), "no-such-thing"}});
        ADD_FAILURE() << block.title << " " << p.key << " = no-such-thing was taken";
      } catch (const InputError& e) {
        EXPECT_EQ(e.key(), block.path(p.key)) << e.what();
      }
      continue;
    }
    try {
      const Scenario sc = load_with(settings);
      if (const B* loaded = block.loaded ? block.loaded(sc) : nullptr) {
        EXPECT_TRUE(agree(p.get(*loaded), value))
            << what << ": the member holds " << shown(p.get(*loaded)) << ", not " << shown(value);
      }
    } catch (const InputError& e) {
      ADD_FAILURE() << what << " was refused: " << e.what();
    }
  }
}

template <class B>
void every_range_is_enforced_at_its_key(const Block<B>& block) {
  for (const Param<B>& p : block.params) {
    if (!p.member || !p.range.bounded()) continue;
    if (p.shape() != ParamShape::kNumber && p.shape() != ParamShape::kInteger) continue;
    const double beyond = !std::isinf(p.range.max) ? p.range.max + 1 : p.range.min - 1;
    const ParamValue v =
        p.shape() == ParamShape::kInteger ? ParamValue(static_cast<long>(beyond)) : ParamValue(beyond);
    const std::string key = block.path(p.key);
    try {
      (void)load_with({{key, yaml_text(v, p.dim)}});
      ADD_FAILURE() << key << " = " << beyond << " is beyond the declared range but was taken";
    } catch (const InputError& e) {
      EXPECT_TRUE(e.key().ends_with(std::string(p.key)))
          << key << ": refused at " << e.key() << ": " << e.what();
    }
  }
}

// The default a declaration states is the one its struct starts with, so code that builds the struct
// itself (tests, library callers) gets what a scenario that leaves the key out gets.
template <class B>
void defaults_are_the_structs(const Block<B>& block) {
  const B defaults = starting<B>();
  const BlockReader reader(YAML::Node(YAML::NodeType::Map), block.title,
                           std::make_shared<const YamlSource>());
  for (const Param<B>& p : block.params) {
    if (!p.member || p.default_text.empty()) continue;
    const std::vector<std::string_view> spellings = p.spellings();
    const ParamValue declared = reader.default_value(p, p.shape(), p.member.point_size(), spellings);
    EXPECT_TRUE(agree(declared, p.get(defaults)))
        << block.title << " " << p.key << ": declared " << p.default_text << ", the struct starts with "
        << shown(p.get(defaults));
  }
}

const Block<slicer::SectionParams> kSections{
    "section",
    slicer::section_params(),
    [](std::string_view key) { return "sections.floor." + std::string(key); },
    [](const Scenario& sc) { return &sc.variants.at(0).sections.at(0); },
    {{"layer_height", {{"sections.floor.bead_width", "100 mm"}}},
     {"variable_height.slope", {{"sections.floor.outline.points", "[[0, 0], [40, 0]]"}}},
     {"variable_height.direction", {{"sections.floor.outline.points", "[[0, 0], [40, 0]]"}}}},
    {{"body", "part"}},
    // A wall shared with another section at the same heights needs a scenario of its own (scenario_test):
    // here its reading shows in a name refused at the key.
    {"shares_wall_with"}};

const Block<Machine> kMachines{
    "machine",
    machine_params(),
    [](std::string_view key) { return "machine." + std::string(key); },
    [](const Scenario& sc) { return &sc.variants.at(0).machine; },
    {{"extruder.output", {{"machine.extruder.max_output", "10 kg/s"}}},
     {"extruder.constant_feed",
      {{"machine.extruder.kind", "filament"}, {"machine.extruder.filament_diameter", "1.75 mm"}}},
     {"gcode.roller_down", {{"machine.gcode.roller_up", "M902"}}},
     {"gcode.roller_up", {{"machine.gcode.roller_down", "M902"}}}}};

const Block<Material> kMaterials{"material", material_params(),
                                 [](std::string_view key) { return "material." + std::string(key); },
                                 [](const Scenario& sc) { return &sc.variants.at(0).material; }};

const Block<OutputSpec> kOutputs{"output", output_params(),
                                 [](std::string_view key) { return "output." + std::string(key); },
                                 [](const Scenario& sc) { return &sc.variants.at(0).output; }};

const Block<ThermalSpec> kThermals{"thermal",
                                   thermal_params(),
                                   [](std::string_view key) { return "thermal." + std::string(key); },
                                   [](const Scenario& sc) { return &sc.variants.at(0).thermal; },
                                   {}};

const Block<RenderSpec> kRenders{"render", render_params(),
                                 [](std::string_view key) { return "render." + std::string(key); },
                                 [](const Scenario& sc) { return &sc.variants.at(0).render; }};

const Block<Tool> kTools{"tool",
                         tool_params(),
                         [](std::string_view key) { return "tools.t." + std::string(key); },
                         nullptr,
                         {{"bead_thickness", {{"tools.t.bead_width", "100 mm"}}}}};

const Block<ProgressSpec> kProgress{
    "progress", progress_params(), [](std::string_view key) { return "render.progress." + std::string(key); },
    [](const Scenario& sc) {
      const auto& p = sc.variants.at(0).render.progress;
      return p ? &*p : nullptr;
    }};

TEST(Declarations, EveryKeyIsReadIntoItsMember) {
  every_key_is_read_into_its_member(kSections);
  every_key_is_read_into_its_member(kMachines);
  every_key_is_read_into_its_member(kMaterials);
  every_key_is_read_into_its_member(kOutputs);
  every_key_is_read_into_its_member(kThermals);
  every_key_is_read_into_its_member(kRenders);
  every_key_is_read_into_its_member(kTools);
  every_key_is_read_into_its_member(kProgress);
}

TEST(Declarations, EveryImageAndViewKeyIsReadIntoItsMember) {
  const auto image = [](const Scenario& sc) { return &sc.variants.at(0).render.images.at(0); };
  for (const Param<ImageSpec>& p : image_params()) {
    if (!p.member) continue;
    const ParamValue value =
        sample(p, p.shape(), p.member.point_size(), p.spellings(), p.get(starting<ImageSpec>()));
    const std::string colour = p.key == "time"     ? "temperature"
                               : p.key == "colour" ? yaml_text(value, p.dim)
                                                   : "layer";
    const std::string map = fmt::format("[{{colour: {}, {}: {}}}]", colour, p.key, yaml_text(value, p.dim));
    const Scenario sc = load_with({{"render.images", map}});
    EXPECT_TRUE(agree(p.get(*image(sc)), value)) << p.key << ": " << shown(p.get(*image(sc)));
  }
  for (const Param<render::CameraSpec>& p : camera_params()) {
    const ParamValue value =
        sample(p, p.shape(), p.member.point_size(), p.spellings(), p.get(starting<render::CameraSpec>()));
    const std::string view = p.key.starts_with("camera.") ? "view: user, " : "";
    const std::string map =
        fmt::format("[{{colour: layer, {}{}: {}}}]", view, p.key, yaml_text(value, p.dim));
    const Scenario sc = load_with({{"render.images", map}});
    EXPECT_TRUE(agree(p.get(image(sc)->camera), value)) << p.key << ": " << shown(p.get(image(sc)->camera));
  }
}

TEST(Declarations, EveryRangeIsEnforcedAtItsKey) {
  every_range_is_enforced_at_its_key(kSections);
  every_range_is_enforced_at_its_key(kMachines);
  every_range_is_enforced_at_its_key(kMaterials);
  every_range_is_enforced_at_its_key(kOutputs);
  every_range_is_enforced_at_its_key(kThermals);
  every_range_is_enforced_at_its_key(kRenders);
  every_range_is_enforced_at_its_key(kTools);
  every_range_is_enforced_at_its_key(kProgress);
}

TEST(Declarations, DefaultsAreTheStructs) {
  defaults_are_the_structs(kSections);
  defaults_are_the_structs(kMachines);
  defaults_are_the_structs(kMaterials);
  defaults_are_the_structs(kOutputs);
  defaults_are_the_structs(kThermals);
  defaults_are_the_structs(kRenders);
  defaults_are_the_structs(kTools);
  defaults_are_the_structs(kProgress);
  defaults_are_the_structs(Block<ImageSpec>{"image", image_params(), nullptr, nullptr});
  defaults_are_the_structs(Block<render::CameraSpec>{"camera", camera_params(), nullptr, nullptr});
  defaults_are_the_structs(Block<Scenario>{"scenario", scenario_params(), nullptr, nullptr});
}

// The keys without a member are read by their block's own code: each refuses a wrong value at its key,
// which it could not if it were never read.
TEST(Declarations, EveryKeyWithoutAMemberIsReadByItsBlock) {
  const std::map<std::string, std::pair<std::string, std::string>> wrong = {
      {"section tool", {"sections.floor.tool", "nosuchtool"}},
      {"section layers", {"sections.floor.layers", "3"}},  // with z: one or the other
      {"section z", {"sections.floor.z", "banana"}},
      {"section fill", {"sections.floor.fill", "[1, 2]"}},
      {"part mesh", {"", "{mesh: no-such-file.stl}"}},
      {"part mesh_units",
       {"",
        "{mesh: " + std::string(BEADTWIN_SOURCE_DIR) + "/tests/bad/nonmanifold.stl, mesh_units: parsecs}"}},
      {"part box.size", {"", "{box: {size: [1 mm, 2 mm]}}"}},
      {"part box.origin", {"", "{box: {size: [10 mm, 10 mm, 10 mm], origin: [0, 0]}}"}},
      {"part open_box.size", {"", "{open_box: {size: [1 mm, 2 mm], wall: 1 mm, floor: 1 mm}}"}},
      {"part open_box.origin", {"part.open_box.origin", "[0, 0]"}},
      {"part open_box.wall", {"part.open_box.wall", "-4 mm"}},
      {"part open_box.floor", {"part.open_box.floor", "-4 mm"}},
      {"tool material", {"tools.t.material", "not-the-material"}},
      {"thermal snapshots", {"thermal.snapshots", "banana"}},
      {"render images", {"render.images", "banana"}},
      {"render progress", {"render.progress", "[1]"}},
  };
  const auto check = [&](const std::string& block, std::string_view key) {
    const auto it = wrong.find(block + " " + std::string(key));
    ASSERT_NE(it, wrong.end()) << block << " " << key << " has no member and no test of its reading here";
    const auto& [path, value] = it->second;
    try {
      // An empty path: the value is the whole part block.
      (void)(path.empty() ? load_with({}, value) : load_with({{path, value}}));
      ADD_FAILURE() << path << " = " << value << " was taken";
    } catch (const InputError& e) {
      EXPECT_TRUE(e.key().find(std::string(key).substr(0, key.find('.'))) != std::string::npos)
          << path << " refused at " << e.key() << ": " << e.what();
    }
  };
  for (const auto& p : slicer::section_params())
    if (!p.member && p.key != "body" && p.key != "shares_wall_with") check("section", p.key);
  for (const auto& p : part_params())
    if (!p.member) check("part", p.key);
  for (const auto& p : tool_params())
    if (!p.member) check("tool", p.key);
  for (const auto& p : thermal_params())
    if (!p.member) check("thermal", p.key);
  for (const auto& p : render_params())
    if (!p.member) check("render", p.key);
}

// The speed word is a letter the G-code reader gives no other meaning, or none: anything else is refused
// at the key, where the machine file says it, not when a program is read.
TEST(Declarations, TheSpeedWordIsRefusedAtItsKeyUnlessTheReaderTakesIt) {
  const auto dir = std::filesystem::temp_directory_path() / "bt_declarations_speed_word";
  std::filesystem::create_directories(dir / "machines");
  const auto machine = dir / "machines" / "speed.yaml";
  std::string scenario = kBase;
  const std::string inline_machine = "{name: m, gcode: {melt_on: M23, melt_off: M24}}";
  scenario.replace(scenario.find(inline_machine), inline_machine.size(), "speed");
  const auto load = [&](std::string_view word) {
    std::ofstream(machine) << fmt::format("name: speed\ngcode:\n  rpm_word: '{}'\n", word);
    return load_scenario_text(scenario, (dir / "s.yaml").string()).variants.at(0).machine.dialect.rpm_word;
  };
  for (const std::string_view word : {"R", "E", "s", "SS", ""}) {
    try {
      (void)load(word);
      ADD_FAILURE() << "speed word '" << word << "' taken";
    } catch (const InputError& e) {
      EXPECT_EQ(e.key(), "machine.gcode.rpm_word") << e.what();
      EXPECT_EQ(std::filesystem::path(e.where().file).filename(), "speed.yaml") << e.what();
      EXPECT_EQ(e.where().line, 3) << e.what();
      EXPECT_EQ(e.where().column, 13) << e.what();
    }
  }
  EXPECT_EQ(load("none"), "");
  for (const std::string_view word : gcode::kSpeedWords) EXPECT_EQ(load(word), word);
  std::filesystem::remove_all(dir);
}

// A short print of the kind the planner makes: heaters on, travel, melt on with a prime at 24 rev/min, three
// beads at 30, 60 and 45 rev/min (the roller down for the first two, up for the third), a reverse, melt off,
// heaters off. A pump of 10 cm³/rev: 1000/6 mm³/s per rev/min.
Toolpath short_print(const Extruder& pump) {
  Toolpath tp;
  const auto dwell = [&](ExtruderEvent e, double seconds, double rpm) {
    Move m;
    m.kind = MoveKind::kDwell;
    m.event = e;
    m.duration_s = seconds;
    m.volume_mm3 = flow_for_rpm(pump, rpm) * seconds;
    m.start = m.end = tp.moves.empty() ? Eigen::Vector3d::Zero() : tp.moves.back().end;
    m.section = 0;
    tp.moves.push_back(m);
  };
  const auto move = [&](MoveKind kind, const Eigen::Vector3d& to, double rpm, bool roller) {
    Move m;
    m.kind = kind;
    m.start = tp.moves.empty() ? Eigen::Vector3d::Zero() : tp.moves.back().end;
    m.end = to;
    m.feed_mm_s = 50.0;
    m.volume_mm3 = flow_for_rpm(pump, rpm) * m.length_mm() / m.feed_mm_s;
    m.roller_down = roller;
    m.feature = kind == MoveKind::kPrint ? Feature::kBoundary : Feature::kTravel;
    m.section = 0;
    m.pass = 0;
    tp.moves.push_back(m);
  };
  dwell(ExtruderEvent::kHeatOn, 0, 0);
  move(MoveKind::kTravel, {0, 0, 5}, 0, false);
  dwell(ExtruderEvent::kMeltOn, 0, 0);
  dwell(ExtruderEvent::kPrime, 1, 24);
  for (const auto& [x, rpm, roller] :
       {std::tuple{100.0, 30.0, true}, {200.0, 60.0, true}, {300.0, 45.0, false}})
    move(MoveKind::kPrint, {x, 0, 5}, rpm, roller);
  dwell(ExtruderEvent::kReverse, 0.5, 0);
  dwell(ExtruderEvent::kMeltOff, 0, 0);
  dwell(ExtruderEvent::kHeatOff, 0, 0);
  tp.sections = {"walls"};
  return tp;
}

// Every code a machine's gcode block sets, and its speed word, reaches the dialect and the reader's options;
// a program written in that dialect reads back event for event (none an unknown code or an unused word),
// with the pump's speeds in rev/min.
TEST(Declarations, EveryMachineCodeReachesTheWriterAndTheReader) {
  std::vector<Setting> settings = {{"machine.extruder.kind", "gear_pump"},
                                   {"machine.extruder.displacement", "10000 mm3"}};
  std::vector<const Param<Machine>*> codes;
  int n = 0;
  for (const Param<Machine>& p : machine_params()) {
    if (!p.none_is_empty) continue;
    codes.push_back(&p);
    // Codes with a decimal, far from the usual M23/M24; a speed word other than S.
    ++n;
    std::string value = fmt::format("M{}.{}", 900 + n, n % 10);
    for (const std::string_view choice : p.spellings())
      if (choice != p.default_text && choice != "none") {
        value = choice;
        break;
      }
    settings.push_back({"machine." + std::string(p.key), value});
  }
  ASSERT_EQ(codes.size(), 13u)
      << "melt, heat, roller, fan, nozzle temperature, prime and reverse codes, and the speed word";
  const Scenario sc = load_with(settings);
  const Machine& m = sc.variants.at(0).machine;
  for (std::size_t i = 0; i < codes.size(); ++i)
    EXPECT_EQ(codes[i]->get(m).text(), settings[i + 2].value) << codes[i]->key;
  EXPECT_NE(m.dialect.rpm_word, "S");

  const gcode::ReaderOptions reader = gcode::reader_options_for(m.dialect, &m.extruder);
  const auto has = [](const std::vector<std::string>& list, const std::string& c) {
    return std::find(list.begin(), list.end(), c) != list.end();
  };
  EXPECT_TRUE(has(reader.melt_on, m.dialect.melt_on));
  EXPECT_TRUE(has(reader.melt_off, m.dialect.melt_off));
  EXPECT_TRUE(has(reader.heat_on, m.dialect.heat_on));
  EXPECT_TRUE(has(reader.heat_off, m.dialect.heat_off));
  EXPECT_TRUE(has(reader.roller_down, m.dialect.roller_down));
  EXPECT_TRUE(has(reader.roller_up, m.dialect.roller_up));
  EXPECT_TRUE(has(reader.prime, m.dialect.prime_code));
  EXPECT_TRUE(has(reader.reverse_on, m.dialect.reverse_on));
  EXPECT_TRUE(has(reader.reverse_off, m.dialect.reverse_off));
  EXPECT_TRUE(has(reader.fan_on, m.dialect.fan_on));
  EXPECT_TRUE(has(reader.fan_off, m.dialect.fan_off));
  EXPECT_TRUE(has(reader.nozzle_temp, m.dialect.nozzle_temp));
  EXPECT_EQ(reader.rpm_word, m.dialect.rpm_word);

  const Toolpath written = short_print(m.extruder);
  gcode::GcodeOptions options;
  options.extruder = &m.extruder;
  MeltSettings reverse;
  reverse.reverse_rpm = 20;
  options.melt = {reverse};
  const std::string program = gcode::write_gcode(written, m.dialect, {}, options);
  // The speed word shows in the speeds read back; the fan and nozzle temperature codes are only read
  // (beadtwin's programs run no part-cooling fan and set no hot end's temperature).
  for (const Param<Machine>* p : codes) {
    const std::string_view key = p->key;
    if (!p->choices.empty() || key.starts_with("gcode.fan") || key == "gcode.nozzle_temp") continue;
    EXPECT_NE(program.find(p->get(m).text()), std::string::npos) << p->key << " not written:\n" << program;
  }
  std::istringstream in(program);
  gcode::ReadStats stats;
  const Toolpath read = gcode::read_gcode(in, "codes.nc", reader, &stats);
  EXPECT_EQ(stats.warning_count(), 0u) << fmt::format("{}", fmt::join(stats.messages, "\n")) << "\n"
                                       << program;

  std::vector<ExtruderEvent> events;
  std::vector<double> rpm;  // of the prime and the beads
  std::vector<bool> roller;
  for (const Move& mv : read.moves) {
    if (mv.kind == MoveKind::kDwell) events.push_back(mv.event);
    if (mv.kind == MoveKind::kPrint || mv.event == ExtruderEvent::kPrime)
      rpm.push_back(rpm_for_flow(m.extruder, commanded_flow_mm3_s(mv)));
    if (mv.kind == MoveKind::kPrint) roller.push_back(mv.roller_down);
  }
  EXPECT_EQ(events, (std::vector<ExtruderEvent>{ExtruderEvent::kHeatOn, ExtruderEvent::kMeltOn,
                                                ExtruderEvent::kPrime, ExtruderEvent::kReverse,
                                                ExtruderEvent::kMeltOff, ExtruderEvent::kHeatOff}))
      << program;
  ASSERT_EQ(rpm.size(), 4u) << program;
  for (std::size_t i = 0; i < rpm.size(); ++i)
    EXPECT_NEAR(rpm[i], (std::array{24.0, 30.0, 60.0, 45.0})[i], 1e-9);
  EXPECT_EQ(roller, (std::vector<bool>{true, true, false}));
}

}  // namespace
}  // namespace beadtwin::scenarios
