// The `ranges:` blocks of material and machine files (scenarios/input/ranges.hpp): read as written, every
// shipped file's ranges valid, and bad ranges refused with the file, line, column and key.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "scenarios/input/scenario.hpp"

namespace beadtwin::scenarios {
namespace {

// A material file, materials/m.yaml beside a scenario in the test's temporary folder, whose ranges block is
// `ranges` (its lines indented by two spaces; the first on line 13); the scenario that prints with it.
std::filesystem::path scenario_with_ranges(const std::string& ranges) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path();
  std::filesystem::create_directories(dir / "materials");
  std::ofstream(dir / "materials" / "m.yaml") << R"(name: m
density: 1140 kg/m3
specific_heat: 1640 J/kgK
conductivity: {along: 0.5 W/mK, across: 0.4 W/mK, through: 0.3 W/mK}
emissivity: 0.85
deposition_temp: 200 C
glass_transition: 110 C
fusion: {viscosity: 1e7 Pa*s, reptation_time: 2 s, required_healing: 0.9,
         healing_ref_temp: 200 C, activation_energy: 150 kJ/mol,
         min_healing_temp: 110 C}
price: 8
ranges:
)" + ranges;
  std::ofstream(dir / "ranges_test.yaml") << R"(name: r
units: {length: mm}
machine: lsam-ph15
material: m
part:
  box: {size: [200, 200, 20]}
sections:
  - name: all
    z: [0, 20]
    layer_height: 5
    bead_width: 20
)";
  return dir / "ranges_test.yaml";
}

InputError range_error(const std::string& ranges) {
  try {
    (void)load_scenario(scenario_with_ranges(ranges));
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError for\n" << ranges;
  return InputError("none");
}

TEST(Ranges, AreReadInEveryFormWithTheirDistributions) {
  const Scenario sc = load_scenario(scenario_with_ranges(R"(  emissivity: [0.8, 0.95]
  conductivity: {scale: [0.7, 1.3]}
  deposition_temp: {distribution: normal, sigma: 5}
  fusion:
    reptation_time: {range: [0.2 s, 20 s], distribution: log-uniform}
)"));
  const Material& m = sc.variants.at(0).material;
  ASSERT_EQ(m.ranges.size(), 4u);
  const InputRange* e = find_range(m.ranges, "emissivity");
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->spread, Spread::kUniform);
  EXPECT_DOUBLE_EQ(e->lo, 0.8);
  EXPECT_DOUBLE_EQ(e->hi, 0.95);
  const InputRange* k = find_range(m.ranges, "conductivity");
  ASSERT_NE(k, nullptr);
  EXPECT_TRUE(k->scale);
  const InputRange* t = find_range(m.ranges, "deposition_temp");
  ASSERT_NE(t, nullptr);
  EXPECT_EQ(t->spread, Spread::kNormal);
  EXPECT_DOUBLE_EQ(t->sigma, 5.0);
  const InputRange* rep = find_range(m.ranges, "fusion.reptation_time");
  ASSERT_NE(rep, nullptr);
  EXPECT_EQ(rep->spread, Spread::kLogUniform);
  EXPECT_DOUBLE_EQ(rep->hi, 20.0);
}

TEST(Ranges, EveryShippedMaterialAndMachineGivesThem) {
  for (const char* material : {"cf-abs-20", "abs", "pla"})
    for (const char* machine : {"lsam-ph15", "desktop-fff", "tma-al-550-filament"}) {
      SCOPED_TRACE(std::string(material) + " on " + machine);
      const Scenario sc = load_scenario_text(
          std::string("name: s\nunits: {length: mm}\nmachine: ") + machine + "\nmaterial: " + material +
              "\npart:\n  box: {size: [200, 200, 20]}\nsections:\n  - name: all\n    z: [0, 20]\n"
              "    layer_height: 5\n    bead_width: 20\n",
          "shipped.yaml");
      const Variant& v = sc.variants.at(0);
      for (const char* key : {"conductivity", "specific_heat", "emissivity", "deposition_temp",
                              "fusion.reptation_time", "fusion.wlf_c1", "fusion.wlf_c2",
                              "fusion.required_healing", "fusion.viscosity", "fusion.max_slump"})
        EXPECT_NE(find_range(v.material.ranges, key), nullptr) << key;
      for (const char* key : {"environment.ambient", "environment.convection", "environment.bed_contact"})
        EXPECT_NE(find_range(v.machine.environment.ranges, key), nullptr) << key;
    }
}

TEST(Ranges, BadRangesNameTheFileLineColumnAndKey) {
  struct Case {
    const char* ranges;
    const char* key;
    const char* says;
  };
  const Case cases[] = {
      {"  emissivity: [0.9, 0.95]\n", "material.ranges.emissivity", "does not contain the value 0.85"},
      {"  emissivity: [0.95, 0.8]\n", "material.ranges.emissivity", "above its high end"},
      {"  emisivity: [0.8, 0.95]\n", "material.ranges.emisivity", "the inputs that take one"},
      {"  conductivity: [0.3 W/mK, 0.6 W/mK]\n", "material.ranges.conductivity", "scale"},
      {"  fusion.reptation_time: {range: [0.2 s, 20 s], distribution: lognormal}\n",
       "material.ranges.fusion.reptation_time", "unknown distribution"},
      {"  deposition_temp: {distribution: normal, range: [190 C, 210 C]}\n",
       "material.ranges.deposition_temp", "sigma"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.ranges);
    const InputError e = range_error(c.ranges);
    EXPECT_TRUE(e.where().file.ends_with("materials/m.yaml")) << e.where().file;
    EXPECT_EQ(e.where().line, 13);  // the range's own line, below `ranges:`
    EXPECT_GT(e.where().column, 2);
    EXPECT_EQ(e.key(), c.key);
    EXPECT_NE(std::string(e.what()).find(c.says), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace beadtwin::scenarios
