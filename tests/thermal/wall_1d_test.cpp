// Tests of the 1-D stacked-layer thermal model against analytic solutions.
#include "thermal/wall_1d.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "tests/thermal/lumped_cooling.hpp"

namespace beadtwin::thermal {
namespace {

// log10 of the WLF shift a(T) referred to T_g (thermal/fusion.hpp), written out for the tests' own
// quadrature.
double wlf_log10(const Material& m, double temp_c) {
  const double above = temp_c - m.glass_transition_c;
  return -m.wlf_c1 * above / (m.wlf_c2_k + above);
}

// A straight LSAM wall: `count` layers of `width_mm` x `length_mm`, one every `period_s`, each deposited
// over its whole period (the next layer starts when it ends).
std::vector<Wall1dLayer> straight_wall(int count, double period_s, double height_mm = 4.064,
                                       double width_mm = 20.0, double length_mm = 1000.0) {
  std::vector<Wall1dLayer> layers;
  for (int i = 0; i < count; ++i) {
    Wall1dLayer layer;
    layer.height_mm = height_mm;
    layer.z_top_mm = height_mm * (i + 1);
    layer.start_s = i * period_s;
    layer.end_s = layer.start_s + period_s;
    layer.area_mm2 = width_mm * length_mm;
    layer.perimeter_mm = 2.0 * (width_mm + length_mm);
    layers.push_back(layer);
  }
  return layers;
}

std::string sci(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3e", value);
  return text;
}

// Heat capacity ρ c_p V of one layer, J/K.
double layer_capacity_J_K(const Material& m, const Wall1dLayer& layer) {
  return m.density_kg_m3 * m.specific_heat_J_kgK * layer.area_mm2 * 1e-6 * layer.height_mm * 1e-3;
}

// Newton's law of cooling of a lumped body (Incropera & DeWitt, Fundamentals of Heat and Mass Transfer,
// 6th ed., §5.2 eq. 5.6): T(t) = T∞ + (T0 − T∞) exp(−t/τ), τ = ρ c_p V / (h A_s), valid when the Biot
// number is small. Returns the largest deviation of the sampled history of layer 0 from it, over (T0 − T∞).
double max_deviation_from_lumped_cooling(const Wall1dResult& result, double t0, double temp0_c,
                                         double ambient_c, double tau_s) {
  double worst = 0.0;
  for (std::size_t k = 0; k < result.sample_times_s.size(); ++k) {
    const double exact =
        ambient_c + (temp0_c - ambient_c) * std::exp(-(result.sample_times_s[k] - t0) / tau_s);
    worst = std::max(worst, std::abs(result.layer_temp_c[0][k] - exact));
  }
  return worst / (temp0_c - ambient_c);
}

TEST(Wall1dTest, SingleLayerCoolsExponentially) {
  // One LSAM bead 21 mm x 5 mm x 1 m on an insulated table, convection only: a lumped body whose free
  // surface is its sides and its top.
  Material material;
  material.emissivity = 0.0;
  Environment env;
  env.bed_insulated = true;
  Wall1dLayer layer{.z_top_mm = 5,
                    .height_mm = 5,
                    .start_s = 0,
                    .end_s = 30,
                    .area_mm2 = 21.0 * 1000.0,
                    .perimeter_mm = 2.0 * (21.0 + 1000.0)};
  const double side_m2 = layer.perimeter_mm * 1e-3 * layer.height_mm * 1e-3;
  const double top_m2 = layer.area_mm2 * 1e-6;
  // Each face through the half node behind it in series with the air (thermal/surface.hpp): area over
  // perimeter across the layer to the sides, half the layer's height to the top.
  const auto series = [&](double depth_mm, double k) {
    return 1.0 / (depth_mm * 1e-3 / k + 1.0 / env.convection_W_m2K);
  };
  const double h_side = series(layer.area_mm2 / layer.perimeter_mm, material.conductivity_across_W_mK);
  const double h_top = series(0.5 * layer.height_mm, material.conductivity_through_W_mK);
  const double tau_s = layer_capacity_J_K(material, layer) / (h_side * side_m2 + h_top * top_m2);

  Wall1dOptions options;
  options.nodes_per_layer = 1;  // one control volume: exactly the lumped body
  options.cooldown_s = 3000;
  const Wall1dResult result = solve_wall_1d(std::span(&layer, 1), material, env, options);
  ASSERT_EQ(result.layer_temp_c.size(), 1u);
  ASSERT_GT(result.sample_times_s.back(), 2.0 * tau_s);  // the history covers several time constants
  const double error =
      max_deviation_from_lumped_cooling(result, 0.0, material.deposition_temp_c, env.ambient_c, tau_s);
  RecordProperty("max_error_fraction", sci(error));
  EXPECT_LT(error, 0.005);  // the brief's criterion
  EXPECT_LT(error, 1e-5);   // what the integrator actually achieves at its default tolerances
  EXPECT_EQ(result.layers[0].verdict, Verdict::kNoInterface);
  EXPECT_DOUBLE_EQ(result.layers[0].substrate_mean_c, env.ambient_c);  // insulated table: ambient
}

TEST(Wall1dTest, WellConductingLayerWithSeveralNodesCoolsLikeTheLumpedBody) {
  // Same bead split into 4 nodes; with a huge conductivity (Biot number ~1e-5) the nodes stay together
  // and the layer must again follow the lumped solution, now with the top loss on the top node only.
  Material material;
  material.emissivity = 0.0;
  material.conductivity_through_W_mK = 1e4;
  material.conductivity_across_W_mK = 1e4;  // the half nodes to the faces vanish too
  Environment env;
  env.bed_insulated = true;
  Wall1dLayer layer{.z_top_mm = 5,
                    .height_mm = 5,
                    .start_s = 0,
                    .end_s = 0,
                    .area_mm2 = 21.0 * 1000.0,
                    .perimeter_mm = 2.0 * (21.0 + 1000.0)};
  const double area_m2 = layer.perimeter_mm * 1e-3 * layer.height_mm * 1e-3 + layer.area_mm2 * 1e-6;
  const double tau_s = layer_capacity_J_K(material, layer) / (env.convection_W_m2K * area_m2);
  Wall1dOptions options;
  options.nodes_per_layer = 4;
  options.cooldown_s = 3000;
  const Wall1dResult result = solve_wall_1d(std::span(&layer, 1), material, env, options);
  const double error =
      max_deviation_from_lumped_cooling(result, 0.0, material.deposition_temp_c, env.ambient_c, tau_s);
  RecordProperty("max_error_fraction", sci(error));
  EXPECT_LT(error, 0.005);
  EXPECT_LT(error, 1e-4);
}

// The same bead with a glass-transition step in c_p (Material::specific_heat_by_temp): a lumped body whose
// cooling follows the separated-variable solution (tests/thermal/lumped_cooling.hpp). Checked as the time
// the model takes to reach each sampled temperature against the analytic time to reach it, relative: within
// 1e-3 (the 1-D model's default tolerances, relative 1e-6, give far less). Its energy is m ∫ c_p dT.
TEST(Wall1dTest, LumpedBodyWithASpecificHeatStepFollowsTheSeparatedVariableSolution) {
  Material material;
  material.emissivity = 0.0;
  material.specific_heat_by_temp = glass_step_specific_heat();
  // A lumped body: no half node between its temperature and its faces.
  material.conductivity_through_W_mK = material.conductivity_across_W_mK = 1e4;
  Environment env;
  env.bed_insulated = true;
  const Wall1dLayer layer{.z_top_mm = 5,
                          .height_mm = 5,
                          .start_s = 0,
                          .end_s = 0,
                          .area_mm2 = 21.0 * 1000.0,
                          .perimeter_mm = 2.0 * (21.0 + 1000.0)};
  const double mass_kg = material.density_kg_m3 * layer.area_mm2 * 1e-6 * layer.height_mm * 1e-3;
  const double ha_W_K =
      env.convection_W_m2K * (layer.perimeter_mm * 1e-3 * layer.height_mm * 1e-3 + layer.area_mm2 * 1e-6);
  Wall1dOptions options;
  options.nodes_per_layer = 1;
  options.cooldown_s = 2500;
  options.sample_interval_s = 10;
  const Wall1dResult result = solve_wall_1d(std::span(&layer, 1), material, env, options);
  const double t0 = material.deposition_temp_c;
  ASSERT_LT(result.layer_temp_c[0].back(), 40.0);  // cooled through the step, to 20 K above the air
  const double worst = max_time_error_fraction(material, mass_kg, ha_W_K, env.ambient_c, t0,
                                               result.sample_times_s, result.layer_temp_c[0]);
  RecordProperty("max_time_error_fraction", sci(worst));
  EXPECT_LT(worst, 1e-3);
  EXPECT_LT(worst, 1e-4);  // what the integrator achieves at its default tolerances (4e-5)
  // Energy relative to the air: m ∫ c_p dT brought in, and what is left at the end.
  EXPECT_NEAR(result.energy_in_J, mass_kg * material.enthalpy_J_kg(env.ambient_c, t0),
              1e-9 * result.energy_in_J);
  const double stored_J = mass_kg * material.enthalpy_J_kg(env.ambient_c, result.layer_temp_c[0].back());
  EXPECT_NEAR(result.energy_stored_J, stored_J, 1e-6 * result.energy_in_J);
  // Stored energy is no longer linear in the state, so the balance holds to the integration error (1e-5).
  EXPECT_LT(result.energy_balance_rel_error, 1e-4);
}

TEST(Wall1dTest, EnergyIsConservedWithRadiationAndAHeatedBed) {
  const Material material;  // ε = 0.85
  const Environment env;    // table held at 65 °C, 100 W/m²K contact
  const std::vector<Wall1dLayer> layers = straight_wall(20, 60.0);
  const Wall1dResult result = solve_wall_1d(layers, material, env);
  RecordProperty("energy_balance_rel_error", sci(result.energy_balance_rel_error));
  EXPECT_LT(result.energy_balance_rel_error, 1e-3);
  EXPECT_LT(result.energy_balance_rel_error, 1e-9);  // BDF keeps linear invariants up to the Newton tolerance

  // Energy brought in: every layer born at the deposition temperature, relative to ambient.
  double in_J = 0.0;
  for (const Wall1dLayer& layer : layers)
    in_J += layer_capacity_J_K(material, layer) * (material.deposition_temp_c - env.ambient_c);
  EXPECT_NEAR(result.energy_in_J, in_J, 1e-9 * in_J);
  // Energy stored, recomputed from the last sample of the history (float precision).
  ASSERT_EQ(result.sample_times_s.back(), result.end_time_s);
  double stored_J = 0.0;
  for (std::size_t i = 0; i < layers.size(); ++i)
    stored_J += layer_capacity_J_K(material, layers[i]) * (result.layer_temp_c[i].back() - env.ambient_c);
  EXPECT_NEAR(result.energy_stored_J, stored_J, 1e-5 * in_J);
  EXPECT_GT(result.energy_lost_J, 0.5 * in_J);  // 30 min of printing and 10 of cooldown lose most of it
}

TEST(Wall1dTest, HistoryIsNaNBeforeALayerExists) {
  const std::vector<Wall1dLayer> layers = straight_wall(3, 40.0);
  const Wall1dResult result = solve_wall_1d(layers, Material{}, Environment{});
  ASSERT_EQ(result.layer_temp_c.size(), 3u);
  EXPECT_DOUBLE_EQ(result.sample_times_s.front(), 0.0);
  EXPECT_DOUBLE_EQ(result.sample_times_s.back(), 120.0 + 600.0);
  for (std::size_t k = 0; k < result.sample_times_s.size(); ++k) {
    const double t = result.sample_times_s[k];
    for (std::size_t i = 0; i < layers.size(); ++i)
      EXPECT_EQ(std::isnan(result.layer_temp_c[i][k]), t < layers[i].start_s) << "layer " << i << " t " << t;
  }
  // Born at the deposition temperature.
  EXPECT_FLOAT_EQ(result.layer_temp_c[1][8], 200.0f);  // t = 40 s
  EXPECT_GT(result.steps, 0);
}

TEST(Wall1dTest, IsothermalInterfaceHealsAsTheFourthRootOfTime) {
  // A printer in an oven: deposition, ambient and table all at 150 °C. No heat flows anywhere, so the
  // interface stays at exactly 150 °C and Yang & Pitchumani's integral reduces to D_h = (t / t_w)^(1/4)
  // (the isothermal reptation result of de Gennes / Wool & O'Connor), t counted from the layer's birth.
  Material material;
  material.deposition_temp_c = 150.0;
  material.viscosity_ref_Pa_s = 1e15;  // nothing slumps: the verdict is about healing only
  Environment env;
  env.ambient_c = env.bed_temp_c = 150.0;
  std::vector<Wall1dLayer> layers = straight_wall(2, 20.0);
  layers[1].end_s = 30.0;  // layer 1 born at 20 s, simulation ends at 30 + 20 s
  Wall1dOptions options;
  options.cooldown_s = 20.0;
  const Wall1dResult result = solve_wall_1d(layers, material, env, options);
  // t_w(150 °C) by the default WLF law, by hand: 10^(17.44 · 90/141.6 − 17.44 · 40/91.6) = 10^3.4690253 s.
  const double expected = std::pow((50.0 - 20.0) / std::pow(10.0, 3.4690253), 0.25);  // 0.3177
  EXPECT_NEAR(result.layers[1].healing, expected, 1e-6);
  EXPECT_EQ(result.layers[1].verdict, Verdict::kTooCold);  // below the required 0.9
  EXPECT_TRUE(std::isnan(result.layers[0].healing));
  for (const auto& history : result.layer_temp_c) {
    for (float temp : history) {
      if (!std::isnan(temp)) {
        EXPECT_FLOAT_EQ(temp, 150.0f);
      }
    }
  }

  // The same oven below the healing threshold: no healing at all.
  material.deposition_temp_c = env.ambient_c = env.bed_temp_c = 100.0;
  EXPECT_EQ(solve_wall_1d(layers, material, env, options).layers[1].healing, 0.0);
}

TEST(Wall1dTest, NonIsothermalHealingMatchesQuadratureOfTheLumpedHistory) {
  // Two equal layers with a huge conductivity cool together as one lumped body (Newton cooling, see
  // above): T(t) = T∞ + (T0 − T∞) exp(−t/τ) with τ = 2 ρ c_p V / (h (2 A_side + A_top)), the lower layer's
  // top being covered. The healing integral ∫ dt / t_w(T(t)) up to the time T reaches the 110 °C threshold
  // is then computed here by Simpson's rule and compared with the solver's D_h.
  Material material;
  material.emissivity = 0.0;
  material.conductivity_through_W_mK = 1e4;
  material.conductivity_across_W_mK = 1e4;
  material.reptation_time_ref_s = 300.0;  // keeps D_h below 1 so that the comparison means something
  Environment env;
  env.bed_insulated = true;
  std::vector<Wall1dLayer> layers = straight_wall(2, 1e-3, 5.0, 21.0, 1000.0);
  Wall1dOptions options;
  options.nodes_per_layer = 1;
  options.cooldown_s = 5000.0;
  const Wall1dResult result = solve_wall_1d(layers, material, env, options);

  const double side_m2 = layers[0].perimeter_mm * 1e-3 * layers[0].height_mm * 1e-3;
  const double top_m2 = layers[0].area_mm2 * 1e-6;
  const double tau_s =
      2.0 * layer_capacity_J_K(material, layers[0]) / (env.convection_W_m2K * (2.0 * side_m2 + top_m2));
  const double excess0 = material.deposition_temp_c - env.ambient_c;
  const double t_threshold = tau_s * std::log(excess0 / (material.healing_min_temp_c - env.ambient_c));
  ASSERT_LT(t_threshold, options.cooldown_s);
  const int intervals = 20000;
  double sum = 0.0;
  for (int k = 0; k <= intervals; ++k) {
    const double t = t_threshold * k / intervals;
    const double temp_c = env.ambient_c + excess0 * std::exp(-t / tau_s);
    // The default WLF law (the whole history lies below its switch at T_g + 100 K).
    const double rate =
        std::pow(10.0, wlf_log10(material, material.healing_ref_temp_c) - wlf_log10(material, temp_c)) /
        material.reptation_time_ref_s;
    sum += (k == 0 || k == intervals ? 1.0 : (k % 2 == 1 ? 4.0 : 2.0)) * rate;
  }
  const double expected = std::pow(sum * t_threshold / intervals / 3.0, 0.25);  // ≈ 0.748
  ASSERT_LT(expected, 0.95);
  RecordProperty("relative_error", sci(std::abs(result.layers[1].healing - expected) / expected));
  EXPECT_NEAR(result.layers[1].healing, expected, 1e-4 * expected);
}

TEST(Wall1dTest, HealingIsConvergedAtTheDefaultTolerances) {
  // Slow layers: every interface crosses the healing threshold while cooling, the hardest case for the
  // integrator (the healing rate jumps there). Tightening the tolerances must not change D_h beyond what
  // the temperature error explains: under the default WLF law d ln(1/t_w)/dT = ln 10 · C1 C2 / (C2 + T −
  // T_g)² ≈ 0.4 /K near 130 °C, so a 1e-3 K error in the interface temperature is 1e-4 in D_h/D_h.
  const std::vector<Wall1dLayer> layers = straight_wall(12, 300.0);
  const Wall1dResult coarse = solve_wall_1d(layers, Material{}, Environment{});
  Wall1dOptions fine;
  fine.rel_tol = 1e-9;
  fine.abs_tol_k = 1e-7;
  const Wall1dResult reference = solve_wall_1d(layers, Material{}, Environment{}, fine);
  for (std::size_t i = 1; i < layers.size(); ++i) {
    EXPECT_GT(reference.layers[i].healing, 0.04);
    EXPECT_LT(reference.layers[i].healing, 0.95);
    EXPECT_NEAR(coarse.layers[i].healing, reference.layers[i].healing, 1e-4) << "layer " << i;
    EXPECT_NEAR(coarse.layers[i].substrate_mean_c, reference.layers[i].substrate_mean_c, 1e-3)
        << "layer " << i;
  }
}

TEST(Wall1dTest, LongerLayerTimesGiveColderSubstrates) {
  const Material material;
  const Environment env;
  double previous_mean = std::numeric_limits<double>::infinity();
  double previous_start = std::numeric_limits<double>::infinity();
  for (double period_s : {10.0, 20.0, 40.0, 80.0, 160.0, 320.0, 640.0}) {
    const Wall1dResult result = solve_wall_1d(straight_wall(10, period_s), material, env);
    const Wall1dLayerResult& top = result.layers.back();
    EXPECT_LT(top.substrate_mean_c, previous_mean) << period_s << " s";
    EXPECT_LT(top.substrate_at_start_c, previous_start) << period_s << " s";
    EXPECT_LE(top.substrate_min_c, top.substrate_mean_c);
    EXPECT_LE(top.substrate_mean_c, top.substrate_max_c);
    // The new layer reheats its substrate: the top node of the layer below gets no colder while it is laid.
    EXPECT_DOUBLE_EQ(top.substrate_min_c, top.substrate_at_start_c);
    previous_mean = top.substrate_mean_c;
    previous_start = top.substrate_at_start_c;
  }
}

// Laid every 5 s, the wall stays soft all through and its slump grows with every layer (more soft height,
// longer under load) until the top layers are too hot; laid every 1000 s, nothing under a layer is soft and
// nothing heals.
TEST(Wall1dTest, ShortLayersAreTooHotAndLongOnesTooCold) {
  const Material material;  // core/material.hpp defaults
  const Environment env;
  constexpr std::size_t kLayers = 20;
  const Wall1dResult fast = solve_wall_1d(straight_wall(kLayers, 5.0), material, env);
  const Wall1dResult slow = solve_wall_1d(straight_wall(kLayers, 1000.0), material, env);
  EXPECT_EQ(fast.layers[0].verdict, Verdict::kNoInterface);
  EXPECT_EQ(slow.layers[0].verdict, Verdict::kNoInterface);
  EXPECT_DOUBLE_EQ(slow.layers[0].substrate_max_c, env.bed_temp_c);
  EXPECT_NE(fast.layers[1].verdict, Verdict::kTooHot);
  for (std::size_t i = 1; i < kLayers; ++i) {
    if (i > 1) {
      EXPECT_GT(fast.layers[i].support.slump_mm, fast.layers[i - 1].support.slump_mm) << "layer " << i;
    }
    if (i >= 15) {
      EXPECT_EQ(fast.layers[i].verdict, Verdict::kTooHot) << "layer " << i;
    }
    EXPECT_EQ(slow.layers[i].support.slump_mm, 0.0);
    EXPECT_EQ(slow.layers[i].verdict, Verdict::kTooCold) << "layer " << i;
    EXPECT_LT(slow.layers[i].healing, material.required_healing);
  }
}

TEST(Wall1dTest, A150LayerComptonWallSolvesInUnderTwoSeconds) {
  // Compton et al. 2017 set-up (docs/physics.md, cooling): 150 layers of 4.064 mm, 20 mm wall (1 m long
  // here), 40 s per layer, 100 min of printing plus 10 min of cooldown.
  const std::vector<Wall1dLayer> layers = straight_wall(150, 40.0);
  const auto t0 = std::chrono::steady_clock::now();
  const Wall1dResult result = solve_wall_1d(layers, Material{}, Environment{});
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  RecordProperty("solve_seconds", sci(seconds));
  RecordProperty("cvode_steps", std::to_string(result.steps));
  EXPECT_LT(seconds, 2.0);
  EXPECT_LT(result.energy_balance_rel_error, 1e-3);
  ASSERT_EQ(result.layers.size(), 150u);
}

TEST(Wall1dTest, BadInputIsAnInputErrorNamingTheField) {
  const Material material;
  const Environment env;
  auto key_of = [&](std::vector<Wall1dLayer> layers, const Material& m = Material{}) -> std::string {
    try {
      solve_wall_1d(layers, m, env);
    } catch (const InputError& e) {
      return e.key();
    }
    return "no error";
  };
  std::vector<Wall1dLayer> layers = straight_wall(4, 40.0);
  EXPECT_EQ(key_of(layers), "no error");

  auto bad = layers;
  bad[2].start_s = bad[1].start_s;  // not increasing
  EXPECT_EQ(key_of(bad), "layers[2].start_s");
  bad = layers;
  bad[3].start_s = 10.0;  // decreasing
  bad[3].end_s = 20.0;
  EXPECT_EQ(key_of(bad), "layers[3].start_s");
  bad = layers;
  bad[1].height_mm = 0.0;
  EXPECT_EQ(key_of(bad), "layers[1].height_mm");
  bad = layers;
  bad[2].area_mm2 = -5.0;
  EXPECT_EQ(key_of(bad), "layers[2].area_mm2");
  bad = layers;
  bad[0].end_s = bad[0].start_s - 1.0;
  EXPECT_EQ(key_of(bad), "layers[0].end_s");
  bad = layers;
  bad[1].perimeter_mm = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(key_of(bad), "layers[1].perimeter_mm");
  EXPECT_EQ(key_of({}), "layers");

  Material m = material;
  m.density_kg_m3 = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(key_of(layers, m), "material.density_kg_m3");
  m = material;
  m.conductivity_through_W_mK = -0.17;
  EXPECT_EQ(key_of(layers, m), "material.conductivity_through_W_mK");
  m = material;
  m.healing_activation_J_mol = -1.0;
  EXPECT_EQ(key_of(layers, m), "material.healing_activation_J_mol");
  m = material;
  m.specific_heat_J_kgK = -1.0;  // not read: the table is used
  m.specific_heat_by_temp = {{20.0, 1200.0}, {200.0, 2000.0}};
  EXPECT_EQ(key_of(layers, m), "no error");
  m.specific_heat_by_temp = {{20.0, 1200.0}, {200.0, 0.0}};
  EXPECT_EQ(key_of(layers, m), "material.specific_heat_by_temp[1]");
  m.specific_heat_by_temp = {{200.0, 1200.0}, {20.0, 2000.0}};
  EXPECT_EQ(key_of(layers, m), "material.specific_heat_by_temp[1]");

  // Every problem is reported at once.
  bad = layers;
  bad[1].height_mm = 0.0;
  bad[3].area_mm2 = 0.0;
  m = material;
  m.specific_heat_J_kgK = -1.0;
  try {
    solve_wall_1d(bad, m, env);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("layers[1].height_mm"), std::string::npos) << what;
    EXPECT_NE(what.find("layers[3].area_mm2"), std::string::npos) << what;
    EXPECT_NE(what.find("material.specific_heat_J_kgK"), std::string::npos) << what;
  }

  Wall1dOptions options;
  options.nodes_per_layer = 0;
  EXPECT_THROW(solve_wall_1d(layers, material, env, options), InputError);
  Environment cold = env;
  cold.ambient_c = -300.0;
  EXPECT_THROW(solve_wall_1d(layers, material, cold), InputError);
}

}  // namespace
}  // namespace beadtwin::thermal
