#include "scenarios/input/scenario.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <gtest/gtest.h>

#include "core/units.hpp"
#include "scenarios/gate_results.hpp"
#include "scenarios/run.hpp"
#include "slicer/polygons.hpp"
#include "tests/read_file.hpp"

namespace beadtwin::scenarios {
namespace {

using testing::read_file;

// A small scenario; tests replace pieces of it to make it wrong in one place.
const std::string kGood = R"(name: small
units: {length: mm}
machine: lsam-ph15
material: cf-abs-20
part:
  open_box: {size: [200, 150, 40], wall: 40, floor: 10}
sections:
  - name: floor
    z: [0, 10]
    layer_height: 5
    bead_width: 20
    boundary: {passes: 2}
    fill: {angle: 0 deg}
  - name: walls
    z: [10, 40]
    layer_height: 5
    bead_width: 20
    boundary: {passes: 1}
    fill: none
variants:
  - name: baseline
  - name: thick
    set: {sections.walls.boundary.passes: 2, machine.environment.bed_temp: 90 C}
gates:
  - porosity < 0.05
)";

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto pos = s.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return s.replace(pos, from.size(), to);
}

InputError load_error(const std::string& text) {
  try {
    (void)load_scenario_text(text, "test.yaml");
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError";
  return InputError("none");
}

TEST(Scenario, DefaultScenarioIsEmbeddedAndValid) {
  const Scenario sc = load_default_scenario();
  EXPECT_EQ(sc.name, "lsam-open-box");
  // The cautious baseline and the faster layers the report's window points to.
  ASSERT_EQ(sc.variants.size(), 2u);
  EXPECT_EQ(sc.variants[1].name, "faster-layers");
  EXPECT_GT(sc.variants[1].sections[1].print_speed_mm_s, sc.variants[0].sections[1].print_speed_mm_s);
  EXPECT_GT(sc.variants[1].sections[0].print_speed_mm_s, sc.variants[0].sections[0].print_speed_mm_s);
  const Variant& v = sc.variants[0];
  ASSERT_EQ(v.sections.size(), 2u);
  EXPECT_EQ(v.sections[0].boundary.passes, 2);
  EXPECT_EQ(v.sections[1].boundary.passes, 3);
  EXPECT_NEAR(v.sections[0].bead_width_mm, 0.83 * 25.4, 1e-9);
  EXPECT_NEAR(v.sections[0].layer_height_mm, 0.2 * 25.4, 1e-9);
  EXPECT_TRUE(v.sections[0].fill.enabled);
  EXPECT_FALSE(v.sections[1].fill.enabled);
  EXPECT_EQ(v.machine.name, "lsam-ph15");
  EXPECT_EQ(v.material.name, "cf-abs-20");
  EXPECT_NEAR(v.material.density_kg_m3, 1140, 1e-9);
  EXPECT_FALSE(sc.gates.empty());
}

TEST(Scenario, VariantsOverrideParameters) {
  const Scenario sc = load_scenario_text(kGood, "test.yaml");
  ASSERT_EQ(sc.variants.size(), 2u);
  EXPECT_EQ(sc.variants[0].sections[1].boundary.passes, 1);
  EXPECT_EQ(sc.variants[1].sections[1].boundary.passes, 2);
  EXPECT_DOUBLE_EQ(sc.variants[0].machine.environment.bed_temp_c, 65);
  EXPECT_DOUBLE_EQ(sc.variants[1].machine.environment.bed_temp_c, 90);
  EXPECT_EQ(sc.variants[1].overrides.at("sections.walls.boundary.passes"), "2");
  // Speed defaults to the extruder's nominal output through the bead: v = Q / A.
  const Variant& v = sc.variants[0];
  const double q = v.machine.extruder_output_kg_s / v.material.density_kg_m3 * 1e9;
  EXPECT_NEAR(v.sections[0].print_speed_mm_s * (5 * 15 + kPi * 25 / 4), q, 1e-6);
}

TEST(Scenario, UnknownKeyNamesFileLineAndKey) {
  const InputError e = load_error(replace(kGood, "boundary: {passes: 2}", "boundary: {pases: 2}"));
  EXPECT_EQ(e.where().file, "test.yaml");
  EXPECT_EQ(e.where().line, 12);
  EXPECT_EQ(e.key(), "sections.floor.boundary.pases");
  EXPECT_NE(std::string(e.what()).find("did you mean 'boundary.passes'"), std::string::npos) << e.what();
  const InputError top = load_error(kGood + "colour: red\n");
  EXPECT_EQ(top.where().line, 26);
  EXPECT_EQ(top.key(), "colour");
}

TEST(Scenario, ASectionThatIsNotAMapIsAnInputErrorAtIt) {
  // A section written as a bare name: yaml-cpp throws its own exception when a scalar is asked for a key
  // (found by tests/fuzz), which would end the program; the loader checks the kind first.
  const InputError e = load_error(replace(kGood, "  - name: walls\n", "  - walls\n  - name: other\n"));
  EXPECT_EQ(e.where().line, 14);
  EXPECT_EQ(e.key(), "sections[1]");
  EXPECT_NE(std::string(e.what()).find("expected a map"), std::string::npos) << e.what();
  // Setting a key of a section by name passes over such an item rather than asking it for its name.
  EXPECT_NE(std::string(load_error(replace(kGood, "set: {sections.walls.boundary.passes: 2,",
                                           "set: {sections.nowhere.boundary.passes: 2,"))
                            .what())
                .find("no section named 'nowhere'"),
            std::string::npos);
}

// --set on the command line: for every variant, after the variant's own settings, and in its overrides.
TEST(Scenario, CommandLineSettingsComeLast) {
  const Scenario sc = load_scenario_text(
      kGood, "test.yaml",
      {parse_setting("sections.walls.boundary.passes=3"), parse_setting("render.width = 640")});
  ASSERT_EQ(sc.variants.size(), 2u);
  for (const Variant& v : sc.variants) {
    EXPECT_EQ(v.sections[1].boundary.passes, 3) << v.name;  // "thick" set 2; the command line wins
    EXPECT_EQ(v.render.width, 640);
    EXPECT_EQ(v.overrides.at("sections.walls.boundary.passes"), "3");
  }
  EXPECT_EQ(sc.variants[1].machine.environment.bed_temp_c, 90.0);  // the variant's other setting stays
  const InputError wrong = [&] {
    try {
      (void)load_scenario_text(kGood, "test.yaml", {parse_setting("sections.walls.boundary.passes=many")});
    } catch (const InputError& e) {
      return e;
    }
    return InputError("none");
  }();
  EXPECT_EQ(wrong.key(), "sections.walls.boundary.passes");
  EXPECT_NE(wrong.where().file.find("--set"), std::string::npos) << wrong.what();
  EXPECT_THROW(parse_setting("no-equals"), InputError);
  EXPECT_THROW(parse_setting("=3"), InputError);
}

TEST(Scenario, WrongUnitAndOutOfRange) {
  const InputError unit =
      load_error(replace(kGood, "layer_height: 5\n    bead_width: 20\n    boundary: {passes: 2}",
                         "layer_height: 5 kg\n    bead_width: 20\n    boundary: {passes: 2}"));
  EXPECT_EQ(unit.where().line, 10);
  EXPECT_EQ(unit.key(), "sections.floor.layer_height");
  EXPECT_NE(std::string(unit.what()).find("unknown unit 'kg' for a length"), std::string::npos)
      << unit.what();
  const InputError range =
      load_error(replace(kGood, "boundary: {passes: 2}", "boundary: {passes: 2, overlap: 80 %}"));
  EXPECT_EQ(range.key(), "sections.floor.boundary.overlap");
  EXPECT_NE(std::string(range.what()).find("out of range"), std::string::npos) << range.what();
  const InputError negative = load_error(replace(kGood, "boundary: {passes: 2}", "boundary: {passes: -1}"));
  EXPECT_EQ(negative.key(), "sections.floor.boundary.passes");
}

TEST(Scenario, MissingRequiredKeysAndBadReferences) {
  const InputError z = load_error(replace(kGood, "    z: [0, 10]\n", ""));
  EXPECT_EQ(z.key(), "sections.floor.z");
  EXPECT_NE(std::string(z.what()).find("required"), std::string::npos);
  const InputError machine = load_error(replace(kGood, "machine: lsam-ph15", "machine: nope"));
  EXPECT_EQ(machine.where().line, 3);
  EXPECT_NE(std::string(machine.what()).find("lsam-ph15"), std::string::npos)
      << "lists what exists: " << machine.what();
  const InputError section = load_error(replace(kGood, "sections.walls.boundary", "sections.wall.boundary"));
  EXPECT_NE(std::string(section.what()).find("no section named 'wall'"), std::string::npos);
  EXPECT_EQ(section.where().line, 23);
  const InputError overlap = load_error(replace(kGood, "z: [10, 40]", "z: [5, 40]"));
  EXPECT_NE(std::string(overlap.what()).find("overlaps section 'floor'"), std::string::npos);
  const InputError syntax = load_error("name: [unclosed\n");
  EXPECT_EQ(syntax.where().line, 2);
}

TEST(Scenario, OverriddenValueErrorsPointAtTheVariant) {
  const InputError e = load_error(
      replace(kGood, "machine.environment.bed_temp: 90 C", "machine.environment.bed_temp: 90 furlongs"));
  EXPECT_EQ(e.where().file, "test.yaml");
  EXPECT_EQ(e.where().line, 23);
  EXPECT_EQ(e.key(), "machine.environment.bed_temp");
}

// The thermal keys: convection by height (heights in the machine block's units unless given),
// snapshot times with `end`, and an even number of cells across is an error at its line.
TEST(Scenario, ThermalKeysAreReadAndCheckedWhereWritten) {
  const std::string with =
      replace(kGood, "gates:", "thermal:\n  snapshots: [10 min, end]\n  cells_across: 5\ngates:");
  const Variant v =
      load_scenario_text(
          replace(with, "    set: {sections.walls.boundary.passes: 2, machine.environment.bed_temp: 90 C}",
                  "    set: {machine.environment.convection_by_height: [[0 mm, 5], [1000 mm, 12]]}"),
          "test.yaml")
          .variants[1];
  ASSERT_EQ(v.machine.environment.convection_by_height.size(), 2u);
  EXPECT_DOUBLE_EQ(v.machine.environment.convection_by_height[1].first, 1000.0);  // mm
  EXPECT_DOUBLE_EQ(v.machine.environment.convection_at(500.0), 8.5);
  EXPECT_EQ(v.thermal.cells_across, 5);
  ASSERT_EQ(v.thermal.snapshot_times_s.size(), 2u);
  EXPECT_DOUBLE_EQ(v.thermal.snapshot_times_s[0], 600.0);
  EXPECT_TRUE(std::isinf(v.thermal.snapshot_times_s[1]));
  const InputError even = load_error(replace(with, "cells_across: 5", "cells_across: 4"));
  EXPECT_EQ(even.key(), "thermal.cells_across");
  EXPECT_NE(std::string(even.what()).find("odd"), std::string::npos);
  const InputError down = load_error(
      replace(kGood, "    set: {sections.walls.boundary.passes: 2, machine.environment.bed_temp: 90 C}",
              "    set: {machine.environment.convection_by_height: [[100, 5], [50, 12]]}"));
  EXPECT_EQ(down.key(), "machine.environment.convection_by_height");
  EXPECT_NE(std::string(down.what()).find("increase"), std::string::npos);
  const InputError snaps = load_error(replace(with, "[10 min, end]", "[10 furlongs]"));
  EXPECT_EQ(snaps.key(), "thermal.snapshots");
  const Variant cp =
      load_scenario_text(
          replace(kGood, "    set: {sections.walls.boundary.passes: 2, machine.environment.bed_temp: 90 C}",
                  "    set: {material.specific_heat_by_temp: [[20 C, 1200], [200 C, 2000]]}"),
          "test.yaml")
          .variants[1];
  EXPECT_DOUBLE_EQ(cp.material.specific_heat_at(110.0), 1600.0);
  const InputError cold = load_error(
      replace(kGood, "    set: {sections.walls.boundary.passes: 2, machine.environment.bed_temp: 90 C}",
              "    set: {material.specific_heat_by_temp: [[200 C, 1200], [20 C, 2000]]}"));
  EXPECT_EQ(cold.key(), "material.specific_heat_by_temp");
  // cf-abs-20 gives a table, which the heat solve uses: a variant setting the one value alone is refused,
  // with the table set to null it is taken.
  const std::string base = "    set: {sections.walls.boundary.passes: 2, machine.environment.bed_temp: 90 C}";
  const InputError alone = load_error(replace(kGood, base, "    set: {material.specific_heat: 1500 J/kgK}"));
  EXPECT_EQ(alone.key(), "material.specific_heat");
  EXPECT_NE(std::string(alone.what()).find("specific_heat_by_temp"), std::string::npos) << alone.what();
  const Variant one = load_scenario_text(replace(kGood, base,
                                                 "    set: {material.specific_heat: 1500 J/kgK, "
                                                 "material.specific_heat_by_temp: null}"),
                                         "test.yaml")
                          .variants[1];
  EXPECT_TRUE(one.material.specific_heat_by_temp.empty());
  EXPECT_DOUBLE_EQ(one.material.specific_heat_at(110.0), 1500.0);
  EXPECT_FALSE(load_scenario_text(kGood, "test.yaml").variants[1].material.specific_heat_by_temp.empty());
}

// The skin by default; the voxel fields for ParaView (about 60 bytes a voxel) when asked for.
TEST(Scenario, OutputFilesForOtherProgramsHaveDefaultsAndCanBeChosen) {
  const Variant def = load_scenario_text(kGood, "test.yaml").variants[0];
  EXPECT_EQ(def.output.skin_format, "ply");
  EXPECT_DOUBLE_EQ(def.output.skin_adaptivity, 0.0);
  EXPECT_FALSE(def.output.write_fields);
  const Scenario chosen = load_scenario_text(
      replace(replace(kGood, "variants:\n",
                      "output: {skin: stl, skin_adaptivity: 0.5, fields: none}\nvariants:\n"),
              "bed_temp: 90 C}", "bed_temp: 90 C, output.skin: none, output.fields: vtu}"),
      "test.yaml");
  EXPECT_EQ(chosen.variants[0].output.skin_format, "stl");
  EXPECT_DOUBLE_EQ(chosen.variants[0].output.skin_adaptivity, 0.5);
  EXPECT_FALSE(chosen.variants[0].output.write_fields);
  EXPECT_EQ(chosen.variants[1].output.skin_format, "");
  EXPECT_TRUE(chosen.variants[1].output.write_fields);
}

TEST(Scenario, UnknownOutputFileTypesNameTheKeyAndTheChoices) {
  const auto with_output = [](const std::string& output) {
    return replace(kGood, "variants:\n", "output: " + output + "\nvariants:\n");
  };
  const InputError skin = load_error(with_output("{skin: obj}"));
  EXPECT_EQ(skin.key(), "output.skin");
  EXPECT_NE(std::string(skin.what()).find("expected one of ply, stl, none but found 'obj'"),
            std::string::npos)
      << skin.what();
  const InputError fields = load_error(with_output("{fields: vti}"));
  EXPECT_EQ(fields.key(), "output.fields");
  EXPECT_NE(std::string(fields.what()).find("expected one of none, vtu but found 'vti'"), std::string::npos)
      << fields.what();
  const InputError adaptivity = load_error(with_output("{skin_adaptivity: 2}"));
  EXPECT_EQ(adaptivity.key(), "output.skin_adaptivity");
}

// The layers whose temperature history the report keeps: the 1st, 15th and 30th by default, a list of layer
// indices from 0, or none; anything else is an error naming the key and where it was written.
TEST(Scenario, HistoryLayersAreAListOfLayerIndices) {
  EXPECT_EQ(load_scenario_text(kGood, "test.yaml").variants[0].output.history_layers,
            (std::vector<int>{0, 14, 29}));
  const auto with_output = [](const std::string& output) {
    return replace(kGood, "variants:\n", "output: " + output + "\nvariants:\n");
  };
  const Scenario chosen =
      load_scenario_text(replace(with_output("{history_layers: [3, 1]}"), "bed_temp: 90 C}",
                                 "bed_temp: 90 C, output.history_layers: []}"),
                         "test.yaml");
  EXPECT_EQ(chosen.variants[0].output.history_layers, (std::vector<int>{3, 1}));
  EXPECT_TRUE(chosen.variants[1].output.history_layers.empty());
  for (const char* bad : {"{history_layers: 5}", "{history_layers: [1, -2]}", "{history_layers: [1.5]}",
                          "{history_layers: [2, 2]}", "{history_layers: [[1]]}"}) {
    SCOPED_TRACE(bad);
    const InputError e = load_error(with_output(bad));
    EXPECT_EQ(e.key(), "output.history_layers");
    EXPECT_EQ(e.where().file, "test.yaml");
    EXPECT_EQ(e.where().line, 20);
  }
  EXPECT_NE(std::string(load_error(with_output("{history_layers: [2, 2]}")).what()).find("twice"),
            std::string::npos);
  EXPECT_NE(std::string(load_error(with_output("{history_layers: [1, -2]}")).what()).find("out of range"),
            std::string::npos);
  // Set by a variant: the message points at the variant's line.
  const InputError set =
      load_error(replace(kGood, "bed_temp: 90 C}", "bed_temp: 90 C, output.history_layers: [x]}"));
  EXPECT_EQ(set.key(), "output.history_layers");
  EXPECT_EQ(set.where().line, 23);
}

TEST(Scenario, RenderBlockListsThePictures) {
  const Variant plain = load_scenario_text(kGood, "test.yaml").variants[0];
  EXPECT_EQ(plain.render.width, 1280);
  EXPECT_FALSE(plain.render.images_given);
  std::vector<std::string> names;
  for (const ImageSpec& im : plain.render.images) names.push_back(im.name);
  EXPECT_EQ(names, (std::vector<std::string>{"fusion", "fusion-top", "sections", "substrate", "deviation"}));
  EXPECT_FALSE(plain.render.progress);

  const auto with_render = [](const std::string& render) {
    return replace(kGood, "variants:\n", "render:\n" + render + "variants:\n");
  };
  const Scenario sc = load_scenario_text(
      replace(with_render("  width: 640\n"
                          "  images:\n"
                          "    - {colour: healing, view: front, range: [0.5, 1]}\n"
                          "    - {name: inside, colour: temperature, time: 1 h, cut: {point: [100, 75, 0]},\n"
                          "       range: [20 C, 240 C]}\n"
                          "    - {colour: layer, view: user, camera: {position: [500, -400, 300]}, "
                          "field_of_view: 0, layer: 3}\n"
                          "  progress: {colour: time, view: top, every: 2}\n"),
              "bed_temp: 90 C}", "bed_temp: 90 C, render.width: 320}"),
      "test.yaml");
  const RenderSpec& r = sc.variants[0].render;
  EXPECT_EQ(r.width, 640);
  EXPECT_EQ(sc.variants[1].render.width, 320);
  ASSERT_EQ(r.images.size(), 3u);
  EXPECT_EQ(r.images[0].name, "healing-front");
  EXPECT_EQ(r.images[0].colour, Colouring::kHealing);
  EXPECT_EQ(r.images[0].camera.view, render::View::kFront);
  ASSERT_TRUE(r.images[0].range);
  EXPECT_DOUBLE_EQ(r.images[0].range->second, 1.0);
  EXPECT_EQ(r.images[1].name, "inside");
  EXPECT_DOUBLE_EQ(r.images[1].time_s, 3600.0);
  ASSERT_TRUE(r.images[1].cut);
  EXPECT_TRUE(r.images[1].cut->normal.isApprox(Eigen::Vector3d(0, -1, 0)));
  EXPECT_DOUBLE_EQ(r.images[1].range->first, 20.0);
  EXPECT_EQ(r.images[2].name, "layer-user");
  EXPECT_EQ(r.images[2].up_to_layer, 3);
  ASSERT_TRUE(r.images[2].camera.position);
  EXPECT_FLOAT_EQ(r.images[2].camera.position->y(), -400.0f);
  EXPECT_EQ(r.images[2].camera.field_of_view_deg, 0.0);
  ASSERT_TRUE(r.progress);
  EXPECT_EQ(r.progress->colour, Colouring::kTime);
  EXPECT_EQ(r.progress->every, 2);
  EXPECT_EQ(r.progress->camera.view, render::View::kTop);

  // Each mistake names its key and line.
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"  images: [{colour: colour}]\n", "render.images[0].colour"},
      {"  images: [{view: top}]\n", "render.images[0].colour"},
      {"  images: [{colour: layer}, {colour: layer}]\n", "render.images[1].name"},
      {"  images: [{colour: layer, camera: {position: [1, 2, 3]}}]\n", "render.images[0].view"},
      {"  images: [{colour: fusion, range: [0, 1]}]\n", "render.images[0].range"},
      {"  images: [{colour: layer, range: [3, 1]}]\n", "render.images[0].range"},
      {"  images: [{colour: layer, time: 5 s}]\n", "render.images[0].time"},
      {"  images: [{colour: layer, cut: {normal: [0, 0, 1]}}]\n", "render.images[0].cut.normal"},
      {"  images: [{colour: layer, cut: {point: [0, 0, 1], normal: [0, 0, 0]}}]\n",
       "render.images[0].cut.normal"},
      {"  images: [{colour: layer, name: a/b}]\n", "render.images[0].name"},
      {"  images: [{colour: layer, colur: 1}]\n", "render.images[0].colur"},
      {"  images: [{colour: layer, field_of_view: 0.5 deg}]\n", "render.images[0].field_of_view"},
      {"  progress: {every: 0}\n", "render.progress.every"},
      {"  progress: 3\n", "render.progress"},
      {"  samples: 0\n", "render.samples"},
      {"  images: {colour: layer}\n", "render.images"},
  };
  for (const auto& [text, key] : bad) {
    SCOPED_TRACE(text);
    const InputError e = load_error(with_render(text));
    EXPECT_EQ(e.key(), key) << e.what();
    EXPECT_EQ(e.where().file, "test.yaml");
    EXPECT_GE(e.where().line, 20);
  }
}

TEST(Gates, ParseAndEvaluate) {
  const InputError bad = load_error(replace(kGood, "porosity < 0.05", "prosity < 0.05"));
  EXPECT_EQ(bad.where().line, 25);
  EXPECT_NE(std::string(bad.what()).find("unknown metric 'prosity'"), std::string::npos);
  EXPECT_THROW((void)load_scenario_text(replace(kGood, "porosity < 0.05", "porosity 0.05"), "t"), InputError);

  Scenario sc = load_scenario_text(
      replace(kGood, "  - porosity < 0.05\n",
              "  - porosity < 0.05\n  - min_stock_mm >= 3\n  - interfaces.too_cold_fraction <= 10 %\n"),
      "t");
  Metrics m;
  m.porosity = 0.01;
  m.too_cold_fraction = 0.2;
  const auto r = evaluate_gates(sc.gates, m);
  ASSERT_EQ(r.size(), 3u);
  EXPECT_TRUE(r[0].passed);
  EXPECT_FALSE(r[1].passed);  // not measured: fails, and says so
  EXPECT_NE(r[1].message.find("not measured"), std::string::npos);
  EXPECT_FALSE(r[2].passed);
  m.too_cold_fraction = 0.1;
  EXPECT_TRUE(evaluate_gates(sc.gates, m)[2].passed);
}

// The pessimistic gate: too cold at the cold end of each interface's band, beside the nominal one.
TEST(Gates, OnTheColdEndOfTheBands) {
  const Scenario sc = load_scenario_text(
      replace(kGood, "  - porosity < 0.05\n",
              "  - interfaces.too_cold_fraction <= 10 %\n  - interfaces.too_cold_fraction_p90 <= 10 %\n"),
      "t");
  Metrics m;
  m.interfaces = 100;
  m.too_cold_fraction = 0.05;
  m.fusion.too_cold_fraction_p90 = 0.15;
  const auto r = evaluate_gates(sc.gates, m);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_TRUE(r[0].passed);
  EXPECT_FALSE(r[1].passed);
  EXPECT_EQ(r[1].value, 0.15);
  m.interfaces = 0;  // nothing measured without interfaces
  EXPECT_NE(evaluate_gates(sc.gates, m)[1].message.find("not measured"), std::string::npos);
}

// A section's figures as sections.NAME.FIGURE: judged on that section's row, refused for a figure that is
// not one, and for a section no variant has, with the sections named.
TEST(Gates, OnASection) {
  Scenario sc = load_scenario_text(
      replace(kGood, "  - porosity < 0.05\n",
              "  - sections.walls.interfaces.too_hot_fraction <= 5 %\n  - sections.floor.mass_kg < 10\n"
              "  - sections.walls.print_time_s <= baseline * 1.05\n"),
      "t");
  ASSERT_EQ(sc.gates.size(), 3u);
  EXPECT_NO_THROW(check_gate_sections(sc));
  Metrics m;
  SectionRow floor, walls;
  floor.name = "floor";
  floor.mass_kg = 12.0;
  walls.name = "walls";
  walls.too_hot_fraction = 0.02;
  walls.print_time_s = 1000.0;
  m.sections = {floor, walls};
  Metrics base = m;
  base.sections[1].print_time_s = 900.0;
  const auto r = evaluate_gates(sc.gates, m, &base);
  EXPECT_TRUE(r[0].passed) << r[0].message;
  EXPECT_EQ(*r[0].value, 0.02);
  EXPECT_FALSE(r[1].passed);  // 12 kg of floor
  EXPECT_EQ(*r[1].value, 12.0);
  EXPECT_FALSE(r[2].passed);  // 1000 s against 900 * 1.05
  EXPECT_DOUBLE_EQ(*r[2].threshold, 945.0);

  // A run without the section (a program's own sections): the gate fails and names the sections there are.
  m.sections = {floor};
  const auto missing = evaluate_gates(sc.gates, m, &base);
  EXPECT_FALSE(missing[0].passed);
  EXPECT_NE(missing[0].message.find("no section 'walls'; its sections are: floor"), std::string::npos)
      << missing[0].message;

  const InputError figure = load_error(replace(kGood, "porosity < 0.05", "sections.walls.colour < 1"));
  EXPECT_NE(std::string(figure.what()).find("sections.NAME. and one of: layers, print_time_s"),
            std::string::npos)
      << figure.what();
  Scenario typo = load_scenario_text(replace(kGood, "porosity < 0.05", "sections.wals.mass_kg < 1"), "t");
  try {
    check_gate_sections(typo);
    ADD_FAILURE() << "no error for a gate on section 'wals'";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "gates");
    EXPECT_EQ(e.where().line, 25);
    EXPECT_NE(std::string(e.what()).find(
                  "names section 'wals', which no variant has; the sections are: floor, walls"),
              std::string::npos)
        << e.what();
  }
}

// Gates relative to the baseline variant: its value of the same metric, scaled or shifted.
TEST(Gates, RelativeToTheBaseline) {
  Scenario sc = load_scenario_text(
      replace(kGood, "  - porosity < 0.05\n",
              "  - print_time_s <= baseline * 1.05\n  - porosity <= baseline + 0.01\n"
              "  - interfaces.too_cold_fraction <= baseline\n  - mass_kg > baseline - 2\n"),
      "t");
  ASSERT_EQ(sc.gates.size(), 4u);
  EXPECT_TRUE(sc.gates[0].relative);
  EXPECT_DOUBLE_EQ(sc.gates[0].factor, 1.05);
  EXPECT_DOUBLE_EQ(sc.gates[1].offset, 0.01);
  EXPECT_DOUBLE_EQ(sc.gates[3].offset, -2.0);
  Metrics base, slower;
  base.print_time_s = 1000.0;
  base.porosity = 0.02;
  base.too_cold_fraction = 0.1;
  base.mass_kg = 50.0;
  slower = base;
  slower.print_time_s = 1060.0;  // 6 % slower: fails the 5 % gate
  slower.porosity = 0.025;
  slower.too_cold_fraction = 0.1;
  slower.mass_kg = 47.0;  // 3 kg lighter: fails "more than 2 kg below"
  const auto r = evaluate_gates(sc.gates, slower, &base);
  EXPECT_FALSE(r[0].passed);
  EXPECT_NE(r[0].message.find("baseline's: 1000"), std::string::npos) << r[0].message;
  ASSERT_TRUE(r[0].threshold);
  EXPECT_DOUBLE_EQ(*r[0].threshold, 1050.0);
  EXPECT_TRUE(r[1].passed);
  EXPECT_TRUE(r[2].passed);
  EXPECT_FALSE(r[3].passed);
  slower.print_time_s = 1049.0;
  EXPECT_TRUE(evaluate_gates(sc.gates, slower, &base)[0].passed);
  // Against itself every relative gate of a non-strict kind passes; with no baseline they fail and say so.
  for (const GateResult& g : evaluate_gates(sc.gates, base, &base)) EXPECT_TRUE(g.passed) << g.expr;
  const auto none = evaluate_gates(sc.gates, slower, nullptr);
  EXPECT_FALSE(none[0].passed);
  EXPECT_NE(none[0].message.find("no baseline"), std::string::npos);
  // Malformed right-hand sides are errors at the gate.
  for (const char* bad :
       {"print_time_s <= baseline / 2", "print_time_s <= baseline * x", "print_time_s <= basline"}) {
    SCOPED_TRACE(bad);
    const InputError e = load_error(replace(kGood, "porosity < 0.05", bad));
    EXPECT_EQ(e.key(), "gates");
    EXPECT_EQ(e.where().line, 25);
  }
}

}  // namespace
}  // namespace beadtwin::scenarios

namespace beadtwin::scenarios {
namespace {

TEST(Scenario, BoundaryStartAndSeamParameters) {
  const std::string text =
      replace(kGood, "    boundary: {passes: 1}\n",
              "    boundary: {passes: 1, reverse_alternate: true, lead_in: 1 in, lead_out: 30}\n"
              "    start_point: [100, 2 in]\n    seam_offset: 25\n");
  const Scenario sc = load_scenario_text(text, "t.yaml");
  const auto& walls = sc.variants[0].sections[1];
  EXPECT_TRUE(walls.boundary.reverse_alternate);
  EXPECT_DOUBLE_EQ(walls.boundary.lead_in_mm, 25.4);
  EXPECT_DOUBLE_EQ(walls.boundary.lead_out_mm, 30);
  EXPECT_DOUBLE_EQ(walls.start_point_mm.x(), 100);
  EXPECT_DOUBLE_EQ(walls.start_point_mm.y(), 50.8);
  EXPECT_DOUBLE_EQ(walls.seam_offset_mm, 25);
  const auto& floor = sc.variants[0].sections[0];
  EXPECT_FALSE(floor.boundary.reverse_alternate);
  EXPECT_DOUBLE_EQ(floor.seam_offset_mm, 0);
  const InputError e = load_error(replace(text, "start_point: [100, 2 in]", "start_point: [100]"));
  EXPECT_EQ(e.key(), "sections.walls.start_point");
}

}  // namespace
}  // namespace beadtwin::scenarios

namespace beadtwin::scenarios {
namespace {

// A part given as a mesh file is read once, repaired, and what was repaired reaches the user.
TEST(Scenario, MeshPartIsReadOnceWithItsRepairsReported) {
  const auto dir = std::filesystem::temp_directory_path() / "bt_scenario_mesh";
  std::filesystem::create_directories(dir);
  // A 100 x 100 x 20 mm box as OBJ, with its top face (two triangles) wound the wrong way.
  std::ofstream(dir / "part.obj") << "v 0 0 0\nv 100 0 0\nv 100 100 0\nv 0 100 0\n"
                                     "v 0 0 20\nv 100 0 20\nv 100 100 20\nv 0 100 20\n"
                                     "f 1 3 2\nf 1 4 3\nf 5 7 6\nf 5 8 7\nf 1 2 6\nf 1 6 5\n"
                                     "f 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
  std::ofstream(dir / "sc.yaml")
      << "name: m\nmachine: lsam-ph15\nmaterial: cf-abs-20\npart: {mesh: part.obj}\n"
         "sections:\n  - {name: a, z: part, layer_height: 5 mm, bead_width: 20 mm}\n"
         "variants:\n  - name: one\n  - name: two\n";
  const Scenario sc = load_scenario(dir / "sc.yaml");
  ASSERT_EQ(sc.variants.size(), 2u);
  EXPECT_EQ(sc.variants[0].part.loaded, sc.variants[1].part.loaded);  // one read for both variants
  EXPECT_NEAR(sc.variants[0].part.loaded->volume_mm3(), 100.0 * 100 * 20, 1e-6);
  EXPECT_NEAR(sc.variants[0].sections[0].z_max_mm, 20, 1e-12);  // z: part
  ASSERT_EQ(sc.warnings.size(), 1u);
  EXPECT_NE(sc.warnings[0].find("2 faces were flipped"), std::string::npos) << sc.warnings[0];
}

}  // namespace
}  // namespace beadtwin::scenarios

#include "scenarios/input/embedded.hpp"

namespace beadtwin::scenarios {
namespace {

// Every scenario shipped in scenarios/ is embedded and loads without error.
TEST(Scenario, EveryShippedScenarioLoads) {
  int count = 0;
  for (const auto& [path, text] : shipped_files()) {
    if (path.find('/') != std::string::npos) continue;  // machines/, materials/
    SCOPED_TRACE(path);
    // From the source tree, where the files a scenario names (meshes, programs) lie beside it.
    const std::filesystem::path file =
        std::filesystem::path(BEADTWIN_SOURCE_DIR) / "scenarios" / "data" / path;
    EXPECT_EQ(read_file(file), text);  // the embedded copy is the file
    const Scenario sc = load_scenario(file);
    EXPECT_FALSE(sc.variants.empty());
    EXPECT_TRUE(!sc.variants[0].sections.empty() || sc.variants[0].program != nullptr);
    ++count;
  }
  EXPECT_GE(count, 2);
  const Scenario fig7 = load_scenario_text(shipped_files().at("fig7-three-sections.yaml"), "<built-in>/fig7");
  ASSERT_EQ(fig7.variants[0].sections.size(), 3u);
  EXPECT_EQ(fig7.variants[0].sections[0].boundary.passes, 2);
  EXPECT_TRUE(fig7.variants[0].sections[0].fill.enabled);
  EXPECT_EQ(fig7.variants[0].sections[1].boundary.passes, 2);
  EXPECT_FALSE(fig7.variants[0].sections[1].fill.enabled);
  EXPECT_EQ(fig7.variants[0].sections[2].boundary.passes, 1);
  EXPECT_EQ(fig7.variants[0].part.tiers.size(), 3u);
}

}  // namespace
}  // namespace beadtwin::scenarios

namespace beadtwin::scenarios {
namespace {

// Sections on different bodies may share heights; `z: part` spans the section's own body.
TEST(Scenario, SectionsOnBodies) {
  const auto dir = std::filesystem::temp_directory_path() / "bt_scenario_bodies";
  std::filesystem::create_directories(dir);
  std::ofstream obj(dir / "two.obj");
  const auto cube = [&obj](const char* name, double x0, double z0, double z1, int base) {
    obj << "o " << name << "\n";
    for (int k = 0; k < 8; ++k)
      obj << "v " << x0 + 100 * (((k + 1) / 2) % 2) << " " << 100 * ((k / 2) % 2) << " " << (k < 4 ? z0 : z1)
          << "\n";
    const int f[12][3] = {{1, 3, 2}, {1, 4, 3}, {5, 6, 7}, {5, 7, 8}, {1, 2, 6}, {1, 6, 5},
                          {2, 3, 7}, {2, 7, 6}, {3, 4, 8}, {3, 8, 7}, {4, 1, 5}, {4, 5, 8}};
    for (const auto& t : f) obj << "f " << t[0] + base << " " << t[1] + base << " " << t[2] + base << "\n";
  };
  cube("tower", 0, 0, 40, 0);
  cube("block", 200, 20, 40, 8);
  obj.close();
  const std::string head =
      "name: b\nmachine: lsam-ph15\nmaterial: cf-abs-20\npart: {mesh: two.obj}\nsections:\n";
  std::ofstream(dir / "ok.yaml")
      << head << "  - {name: t, body: tower, z: part, layer_height: 5 mm, bead_width: 20 mm}\n"
      << "  - {name: k, body: block, z: part, layer_height: 5 mm, bead_width: 20 mm}\n";
  const Scenario sc = load_scenario(dir / "ok.yaml");
  ASSERT_EQ(sc.variants[0].sections.size(), 2u);
  EXPECT_DOUBLE_EQ(sc.variants[0].sections[1].z_min_mm, 20);
  EXPECT_DOUBLE_EQ(sc.variants[0].sections[1].z_max_mm, 40);
  std::ofstream(dir / "bad.yaml")
      << head << "  - {name: t, body: tower, z: part, layer_height: 5 mm, bead_width: 20 mm}\n"
      << "  - {name: k, body: nope, z: part, layer_height: 5 mm, bead_width: 20 mm}\n";
  try {
    (void)load_scenario(dir / "bad.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "sections.k.body");
    EXPECT_NE(std::string(e.what()).find("tower, block"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "overlap.yaml")
      << head << "  - {name: t, z: part, layer_height: 5 mm, bead_width: 20 mm}\n"
      << "  - {name: k, body: block, z: part, layer_height: 5 mm, bead_width: 20 mm}\n";
  EXPECT_THROW((void)load_scenario(dir / "overlap.yaml"), InputError);
}

}  // namespace
}  // namespace beadtwin::scenarios

namespace beadtwin::scenarios {
namespace {

// Tool / melt configurations (patent (48)): sections take their bead from the tool they name.
TEST(Scenario, SectionsTakeTheirBeadFromTheirTool) {
  const std::string tools =
      "tools:\n  big: {bead_width: 1 in, bead_thickness: 0.25 in, material: cf-abs-20}\n"
      "  small: {bead_width: 10 mm, bead_thickness: 2 mm}\nsections:\n";
  std::string text = replace(kGood, "sections:\n", tools);
  text = replace(text, "    layer_height: 5\n    bead_width: 20\n    boundary: {passes: 2}",
                 "    tool: big\n    boundary: {passes: 2}");
  text = replace(text, "    layer_height: 5\n    bead_width: 20\n    boundary: {passes: 1}",
                 "    tool: small\n    bead_width: 12\n    boundary: {passes: 1}");
  const Scenario sc = load_scenario_text(text, "t.yaml");
  const auto& floor = sc.variants[0].sections[0];
  EXPECT_DOUBLE_EQ(floor.bead_width_mm, 25.4);
  EXPECT_DOUBLE_EQ(floor.layer_height_mm, 6.35);
  const auto& walls = sc.variants[0].sections[1];
  EXPECT_DOUBLE_EQ(walls.bead_width_mm, 12);  // the section's own value wins
  EXPECT_DOUBLE_EQ(walls.layer_height_mm, 2);

  const InputError unknown = load_error(replace(text, "tool: small", "tool: tiny"));
  EXPECT_EQ(unknown.key(), "sections.walls.tool");
  EXPECT_NE(std::string(unknown.what()).find("big, small"), std::string::npos) << unknown.what();
  const InputError other = load_error(replace(text, "material: cf-abs-20}", "material: pla}"));
  EXPECT_EQ(other.key(), "tools.big.material");
  const InputError key = load_error(replace(text, "bead_thickness: 2 mm", "bead_thicknes: 2 mm"));
  EXPECT_EQ(key.key(), "tools.small.bead_thicknes");
}

}  // namespace
}  // namespace beadtwin::scenarios

namespace beadtwin::scenarios {
namespace {

TEST(Scenario, OutlineSectionsNeedNoPart) {
  const std::string text =
      "name: o\nmachine: lsam-ph15\nmaterial: cf-abs-20\nunits: {length: mm}\nsections:\n"
      "  - name: wall\n    layers: 12\n    layer_height: 5\n    bead_width: 20\n"
      "    outline: {points: [[0, 0], [500, 0], [500, 300]], closed: false}\n";
  const Scenario sc = load_scenario_text(text, "o.yaml");
  const auto& s = sc.variants[0].sections[0];
  ASSERT_EQ(s.outline_path.size(), 3u);
  EXPECT_FALSE(s.outline_closed);
  EXPECT_DOUBLE_EQ(s.z_max_mm, 60);
  // A slicing section without a part is an error naming the section.
  const InputError e = load_error(text + "  - {name: cut, z: [60, 80]}\n");
  EXPECT_EQ(e.key(), "sections.cut");
  EXPECT_NE(std::string(e.what()).find("no part"), std::string::npos);
  EXPECT_THROW((void)load_scenario_text(replace(text, "layers: 12", "layers: 12\n    z: [0, 10]"), "o"),
               InputError);
}

}  // namespace
}  // namespace beadtwin::scenarios

namespace beadtwin::scenarios {
namespace {

// The general and process parameters of patent (41)-(47) read from a scenario, and their mistakes named.
TEST(Scenario, ContainmentSlicePlaneSharedWallSmoothingAndVoids) {
  const std::string text = replace(kGood, "    boundary: {passes: 1}\n    fill: none\n",
                                   "    boundary: {passes: 1, max_overlap: 40 %}\n    fill: none\n"
                                   "    containment: {outside: [[0, 0], [100, 0], [100, 150], [0, 150]],\n"
                                   "                  inside: [[[10, 10], [20, 10], [20, 20]], [[30, 30], "
                                   "[40, 30], [40, 40]]]}\n"
                                   "    slice_plane: top\n    shares_wall_with: floor\n"
                                   "    combine_stock_offset: true\n    arc_chord_tolerance: 0.5\n"
                                   "    pull_back: {length: 30, extension: 10}\n"
                                   "    smoothing: {smooth_curves: true, never_start_in_corner: true, "
                                   "min_polygon_angle: 45 deg}\n"
                                   "    voids: {detect: true, fill: true, min_width: 4}\n");
  const Scenario sc = load_scenario_text(text, "t.yaml");
  const slicer::SectionParams& s = sc.variants[0].sections[1];
  EXPECT_NEAR(slicer::area_mm2(s.containment_outside), 100.0 * 150, 1e-9);
  EXPECT_EQ(s.containment_inside.size(), 2u);
  EXPECT_EQ(s.shares_wall_with, "floor");
  EXPECT_TRUE(s.combine_stock_offset);
  EXPECT_DOUBLE_EQ(s.arc_chord_tolerance_mm, 0.5);
  EXPECT_DOUBLE_EQ(s.boundary.max_overlap, 0.4);
  EXPECT_DOUBLE_EQ(s.pull_back.length_mm, 30);
  EXPECT_DOUBLE_EQ(s.pull_back.extension_mm, 10);
  EXPECT_TRUE(s.smoothing.smooth_curves && s.smoothing.never_start_in_corner);
  EXPECT_DOUBLE_EQ(s.smoothing.min_polygon_angle_deg, 45);
  EXPECT_TRUE(s.voids.detect && s.voids.fill);
  EXPECT_DOUBLE_EQ(s.voids.min_width_mm, 4);

  EXPECT_EQ(load_error(replace(text, "slice_plane: top", "slice_plane: diagonal")).key(),
            "sections.walls.slice_plane");
  const InputError self = load_error(replace(text, "shares_wall_with: floor", "shares_wall_with: walls"));
  EXPECT_EQ(self.key(), "sections.walls.shares_wall_with");
  EXPECT_GT(self.where().line, 0);
  EXPECT_EQ(load_error(replace(text, "max_overlap: 40 %", "max_overlap: 5 %")).key(),
            "sections.walls.boundary.max_overlap");
  EXPECT_EQ(load_error(replace(text, "inside: [[[10, 10]", "inside: [[[10]")).key(),
            "sections.walls.containment.inside");
  // A point beyond 100 m (found by tests/fuzz: beyond the polygon clipper's range its exception ended the
  // program).
  const InputError far =
      load_error(replace(text, "inside: [[[10, 10]", "inside: [[[3333333333333333333333, 10]"));
  EXPECT_EQ(far.key(), "sections.walls.containment.inside");
  EXPECT_NE(std::string(far.what()).find("more than 100 m from the origin; are the units right?"),
            std::string::npos)
      << far.what();
  EXPECT_EQ(load_error(replace(text, "outside: [[0, 0]", "outside: [[0, -1e300]")).key(),
            "sections.walls.containment.outside");
  EXPECT_EQ(load_error(replace(text, "extension: 10}", "extension: 10, angle: 3}")).key(),
            "sections.walls.pull_back.angle");
}

// Arc chord tolerance (patent (45)): with a dialect that takes arcs, a round outline is written as G2/G3.
TEST(Scenario, ArcChordToleranceWritesArcs) {
  std::string text =
      "name: o\nmachine: lsam-ph15\nmaterial: cf-abs-20\nunits: {length: mm}\nsections:\n"
      "  - name: ring\n    layers: 2\n    layer_height: 5\n    bead_width: 20\n"
      "    arc_chord_tolerance: 0.05\n    outline: {points: [";
  for (int i = 0; i < 360; ++i)
    text += fmt::format("{}[{:.4f}, {:.4f}]", i ? ", " : "", 300 + 200 * std::cos(i * kPi / 180),
                        300 + 200 * std::sin(i * kPi / 180));
  text += "]}\nvariants:\n  - name: lines\n  - name: arcs\n    set: {machine.gcode.arcs: true}\n";
  const Scenario sc = load_scenario_text(text, "ring.yaml");
  auto count = [](const std::string& program, const std::string& code) {
    std::size_t n = 0;
    for (std::size_t at = program.find("\n" + code + " "); at != std::string::npos;
         at = program.find("\n" + code + " ", at + 1))
      ++n;
    return n;
  };
  const std::string lines = slice_program(sc, "lines"), arcs = slice_program(sc, "arcs");
  EXPECT_EQ(count(lines, "G3") + count(lines, "G2"), 0u);
  EXPECT_GE(count(lines, "G1"), 2u * 359);
  EXPECT_GE(count(arcs, "G3"), 2u * 2);  // at most 180 degrees an arc
  EXPECT_LT(count(arcs, "G1") + count(arcs, "G3"), count(lines, "G1") / 10);
}

// Corner pull-back (patent (47)) in the program: the machine's roller codes around every corner.
TEST(Scenario, PullBackWritesTheMachinesRollerCodes) {
  const std::string text =
      "name: o\nmachine: lsam-ph15\nmaterial: cf-abs-20\nunits: {length: mm}\nsections:\n"
      "  - name: square\n    layers: 1\n    layer_height: 5\n    bead_width: 20\n    start_point: [100, 0]\n"
      "    pull_back: {length: 30, extension: 10}\n"
      "    outline: {points: [[0, 0], [200, 0], [200, 200], [0, 200]]}\n"
      "variants:\n  - name: plain\n  - name: codes\n"
      "    set: {machine.gcode.roller_down: M60, machine.gcode.roller_up: M61}\n";
  const Scenario sc = load_scenario_text(text, "sq.yaml");
  auto count = [](const std::string& program, const std::string& code) {
    std::size_t n = 0;
    for (std::size_t at = program.find("\n" + code + "\n"); at != std::string::npos;
         at = program.find("\n" + code + "\n", at + 1))
      ++n;
    return n;
  };
  const std::string codes = slice_program(sc, "codes");
  EXPECT_EQ(count(codes, "M61"), 4u);  // up before each of the four corners
  EXPECT_EQ(count(codes, "M60"), 5u);  // down at the start and after each corner
  EXPECT_EQ(slice_program(sc, "plain").find("M61"), std::string::npos);
  EXPECT_EQ(load_error(replace(text, "roller_up: M61", "roller_up: none")).key(),
            "machine.gcode.roller_down");
}

}  // namespace
}  // namespace beadtwin::scenarios

namespace beadtwin::scenarios {
namespace {

// A PrusaSlicer program timed by our motion model on the desktop machine agrees with
// PrusaSlicer's own estimate written in the program ("estimated printing time (normal mode)") within 10 %.
TEST(ProgramCheck, TimingAgreesWithPrusaSlicersEstimate) {
  const std::filesystem::path sample =
      std::filesystem::path(BEADTWIN_SOURCE_DIR) / "tests/data/prusa_box.gcode";
  ProgramCheck check;
  check.program = sample;
  const Scenario sc = load_program_check(check);
  ASSERT_EQ(sc.variants.size(), 1u);
  const Variant& v = sc.variants[0];
  EXPECT_EQ(v.machine.name, "desktop-fff");  // inferred from the E words
  ASSERT_TRUE(v.program);
  Toolpath tp = *v.program;
  time_toolpath(tp, v.machine.motion);
  // PrusaSlicer's estimate, "; estimated printing time (normal mode) = 2m 3s".
  std::ifstream in(sample);
  double estimate_s = -1;
  for (std::string line; std::getline(in, line);) {
    const std::string key = "; estimated printing time (normal mode) = ";
    if (line.rfind(key, 0) != 0) continue;
    int h = 0, m = 0, s = 0;
    const std::string t = line.substr(key.size());
    if (std::sscanf(t.c_str(), "%dh %dm %ds", &h, &m, &s) == 3)
      estimate_s = 3600.0 * h + 60.0 * m + s;
    else if (std::sscanf(t.c_str(), "%dm %ds", &m, &s) == 2)
      estimate_s = 60.0 * m + s;
  }
  ASSERT_GT(estimate_s, 0);
  EXPECT_NEAR(tp.total_time_s() / estimate_s, 1.0, 0.10) << tp.total_time_s() << " s against " << estimate_s;
  // The machine is said to be assumed.
  ASSERT_FALSE(sc.warnings.empty());
  EXPECT_NE(sc.warnings.front().find("assumed machine desktop-fff"), std::string::npos);
}

// The material a check assumes: the program's stated filament type where beadtwin ships it (PrusaSlicer's
// settings block, "; filament_type = PLA" in tests/data/prusa_box.gcode), the shipped CF-ABS otherwise, and
// always said; a material given wins.
TEST(ProgramCheck, MaterialFromTheProgramsFilamentType) {
  ProgramCheck check;
  check.program = std::filesystem::path(BEADTWIN_SOURCE_DIR) / "tests/data/prusa_box.gcode";
  EXPECT_EQ(stated_filament_type(check.program), "PLA");
  Scenario sc = load_program_check(check);
  EXPECT_EQ(sc.variants.front().material.name, "pla");
  const auto said = [](const Scenario& s, const std::string& text) {
    return std::any_of(s.warnings.begin(), s.warnings.end(),
                       [&](const std::string& w) { return w.find(text) != std::string::npos; });
  };
  EXPECT_TRUE(said(sc, "assumed material pla (the program says filament_type = PLA)"));

  check.material = "abs";
  sc = load_program_check(check);
  EXPECT_EQ(sc.variants.front().material.name, "abs");
  EXPECT_FALSE(said(sc, "assumed material"));

  const auto dir = std::filesystem::temp_directory_path() / "bt_check_material";
  std::filesystem::create_directories(dir);
  const std::string moves = "G21\nG90\nM83\nG1 Z0.3 F600\nG1 X20 Y0 E1\nG1 X20 Y20 E1\n";
  for (const auto& [settings, material, message] :
       {std::tuple<std::string, std::string, std::string>{"; filament_type = ABS;PLA\n", "abs",
                                                          "filament_type = ABS)"},
        {"; filament_type = PETG\n", "cf-abs-20", "filament_type PETG is not one beadtwin ships"},
        {"; layer_height = 0.2\n", "cf-abs-20", "assumed material cf-abs-20 (the shipped material)"}}) {
    SCOPED_TRACE(settings);
    ProgramCheck c;
    c.program = dir / "p.gcode";
    std::ofstream(c.program) << moves << settings;
    const Scenario s = load_program_check(c);
    EXPECT_EQ(s.variants.front().material.name, material);
    EXPECT_TRUE(said(s, message)) << fmt::format("{}", fmt::join(s.warnings, " | "));
  }
}

// The program's heater codes set the beads' temperature (gcode.nozzle_temp, M104 and M109 by default); a
// machine whose bead is measured colder than its set point turns them off, and the material's
// deposition_temp lays the beads.
TEST(ProgramCheck, TheMachineSaysWhetherTheProgramsHeaterCodesSetTheBeadsTemperature) {
  const auto dir = std::filesystem::temp_directory_path() / "bt_check_nozzle_temp";
  std::filesystem::create_directories(dir);
  ProgramCheck check;
  check.program = dir / "p.gcode";
  check.machine = "desktop-fff";
  check.material = "pla";
  std::ofstream(check.program) << "G21\nG90\nM83\nM104 S215\nG1 Z0.3 F600\nG1 X20 Y0 E1\nM109 S230\n"
                                  "G1 X20 Y20 E1\n";
  const auto nozzle = [](const Scenario& s) {
    std::vector<float> c;
    for (const Move& m : s.variants.front().program->moves)
      if (m.deposits()) c.push_back(m.nozzle_c);
    return c;
  };
  const std::vector<float> set = nozzle(load_program_check(check));
  ASSERT_EQ(set.size(), 2u);
  EXPECT_FLOAT_EQ(set[0], 215.0f);
  EXPECT_FLOAT_EQ(set[1], 230.0f);
  check.settings = {{"machine.gcode.nozzle_temp", "none"}};
  const Scenario ignored = load_program_check(check);
  EXPECT_EQ(ignored.variants.front().machine.dialect.nozzle_temp, "");
  for (const float c : nozzle(ignored)) EXPECT_TRUE(std::isnan(c));
  check.settings = {{"machine.gcode.nozzle_temp", "M109"}};
  const std::vector<float> only_m109 = nozzle(load_program_check(check));
  ASSERT_EQ(only_m109.size(), 2u);
  EXPECT_TRUE(std::isnan(only_m109[0]));
  EXPECT_FLOAT_EQ(only_m109[1], 230.0f);
}

// The same for CuraEngine: its estimate is the last ";TIME_ELAPSED:" of the program
// (tests/data/cura_box.gcode, CuraEngine 4.13 with Cura's fdmprinter definition, 2.85 mm filament).
TEST(ProgramCheck, TimingAgreesWithCuraEnginesEstimate) {
  const std::filesystem::path sample =
      std::filesystem::path(BEADTWIN_SOURCE_DIR) / "tests/data/cura_box.gcode";
  ProgramCheck check;
  check.program = sample;
  const Scenario sc = load_program_check(check);
  ASSERT_EQ(sc.variants.size(), 1u);
  const Variant& v = sc.variants[0];
  EXPECT_EQ(v.machine.name, "desktop-fff");
  ASSERT_TRUE(v.program);
  Toolpath tp = *v.program;
  time_toolpath(tp, v.machine.motion);
  std::ifstream in(sample);
  double estimate_s = -1;
  for (std::string line; std::getline(in, line);)
    if (line.rfind(";TIME_ELAPSED:", 0) == 0) estimate_s = std::stod(line.substr(14));
  ASSERT_GT(estimate_s, 0);
  EXPECT_NEAR(tp.total_time_s() / estimate_s, 1.0, 0.10) << tp.total_time_s() << " s against " << estimate_s;
}

}  // namespace
}  // namespace beadtwin::scenarios
