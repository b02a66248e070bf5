// The shipped material library: every file loads through a scenario and holds physically sensible values.
#include <algorithm>
#include <string>
#include <vector>

#include <fmt/format.h>

#include <gtest/gtest.h>

#include "scenarios/input/embedded.hpp"
#include "scenarios/input/scenario.hpp"

namespace beadtwin::scenarios {
namespace {

// The names of the shipped materials: materials/NAME.yaml among the embedded files.
std::vector<std::string> shipped_materials() {
  std::vector<std::string> names;
  const std::string prefix = "materials/", suffix = ".yaml";
  for (const auto& [path, text] : shipped_files())
    if (path.starts_with(prefix) && path.ends_with(suffix))
      names.push_back(path.substr(prefix.size(), path.size() - prefix.size() - suffix.size()));
  return names;
}

Material load_material(const std::string& name) {
  const std::string text = fmt::format(R"(name: m
units: {{length: mm}}
machine: lsam-ph15
material: {}
part:
  box: {{size: [200, 200, 20]}}
sections:
  - name: all
    z: [0, 20]
    layer_height: 5
    bead_width: 20
)",
                                       name);
  const Scenario sc = load_scenario_text(text, "materials_test.yaml");
  EXPECT_EQ(sc.variants.size(), 1u);
  return sc.variants.at(0).material;
}

TEST(Materials, ShippedLibraryHoldsTheReferenceAndNeatPolymers) {
  const std::vector<std::string> names = shipped_materials();
  for (const char* expected : {"cf-abs-20", "abs", "pla"})
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
}

// Each shipped material loads, is named after its file, and has positive physical values and a fusion
// window in a sensible order.
TEST(Materials, EveryShippedMaterialLoadsWithSensibleValues) {
  for (const std::string& name : shipped_materials()) {
    SCOPED_TRACE(name);
    const Material m = load_material(name);
    EXPECT_EQ(m.name, name);
    EXPECT_GT(m.density_kg_m3, 0.0);
    EXPECT_GT(m.specific_heat_J_kgK, 0.0);
    EXPECT_GT(m.conductivity_along_W_mK, 0.0);
    EXPECT_GT(m.conductivity_across_W_mK, 0.0);
    EXPECT_GT(m.conductivity_through_W_mK, 0.0);
    EXPECT_GT(m.emissivity, 0.0);
    EXPECT_LE(m.emissivity, 1.0);
    EXPECT_GT(m.reptation_time_ref_s, 0.0);
    EXPECT_GT(m.healing_activation_J_mol, 0.0);
    EXPECT_GE(m.price_per_kg, 0.0);
    // Fusion window: heals only above the minimum, soft above the softening temperature; the bead is laid
    // hotter than both and than T_g, and what is under it flows like a melt at most there.
    EXPECT_LT(m.healing_min_temp_c, m.deposition_temp_c);
    EXPECT_LT(m.softening_temp_c, m.deposition_temp_c);
    EXPECT_GE(m.viscosity_ref_Pa_s, 100.0);
    EXPECT_GT(m.max_slump, 0.0);
    EXPECT_LT(m.glass_transition_c, m.deposition_temp_c);
    EXPECT_GE(m.healing_min_temp_c, m.glass_transition_c) << "heals in the glass";
    EXPECT_GT(m.healing_ref_temp_c, m.healing_min_temp_c);
    EXPECT_GT(m.required_healing, 0.0);
    EXPECT_LE(m.required_healing, 1.0);
    // Amorphous (PLA printed largely so): WLF from T_g, with constants of the usual size (the universal
    // 17.44 and 51.6 K where nothing was measured) and the Arrhenius part above T_g + ~100 K.
    EXPECT_EQ(m.healing_law, HealingLaw::kWlf);
    EXPECT_GE(m.wlf_c1, 10.0);
    EXPECT_LE(m.wlf_c1, 40.0);
    EXPECT_GE(m.wlf_c2_k, 25.0);
    EXPECT_LE(m.wlf_c2_k, 120.0);
    EXPECT_GE(m.wlf_range_k, 50.0);
    EXPECT_LE(m.wlf_range_k, 150.0);
  }
}

// Each shipped material gives its specific heat by temperature with the step of the glass transition: c_p
// rises across T_g +- 5 K by more than a tenth of its room-temperature value (a glass alone rises by about
// 4 % over 10 K), never falls with temperature, and stays between 1000 and 2500 J/kg·K from room temperature
// to the deposition temperature (amorphous polymers and their carbon-fibre compounds: docs/physics.md,
// Cooling).
TEST(Materials, SpecificHeatRisesWithTheGlassTransitionStep) {
  for (const std::string& name : shipped_materials()) {
    SCOPED_TRACE(name);
    const Material m = load_material(name);
    ASSERT_FALSE(m.specific_heat_by_temp.empty());
    const double tg = m.glass_transition_c, room = m.specific_heat_at(23.0);
    EXPECT_GT(m.specific_heat_at(tg + 5.0) - m.specific_heat_at(tg - 5.0), 0.1 * room);
    for (double t = 0.0; t <= m.deposition_temp_c; t += 1.0) {
      EXPECT_GE(m.specific_heat_at(t + 1.0), m.specific_heat_at(t)) << t << " C";
      if (t >= 20.0) {
        EXPECT_GT(m.specific_heat_at(t), 1000.0) << t << " C";
        EXPECT_LT(m.specific_heat_at(t), 2500.0) << t << " C";
      }
    }
  }
}

// Neat polymers conduct heat alike in every direction; their files say so with three equal values.
TEST(Materials, NeatPolymersAreIsotropic) {
  for (const char* name : {"abs", "pla"}) {
    SCOPED_TRACE(name);
    const Material m = load_material(name);
    EXPECT_EQ(m.conductivity_along_W_mK, m.conductivity_across_W_mK);
    EXPECT_EQ(m.conductivity_along_W_mK, m.conductivity_through_W_mK);
  }
}

}  // namespace
}  // namespace beadtwin::scenarios
