// Tests of the 3-D heat transfer on the thermal mesh (thermal/heat.hpp) against analytic solutions. The
// meshes are built by hand — a ThermalMesh is a plain struct — so that each test checks the solver alone:
// cells of known capacity, links of known area and distance, open and table area where the analytic problem
// has its boundaries.
#include "thermal/heat.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/units.hpp"
#include "tests/thermal/lumped_cooling.hpp"
#include "tests/thermal/test_meshes.hpp"

namespace beadtwin::thermal {
namespace {

constexpr double kKelvinOffset = 273.15;

std::string sci(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3e", value);
  return text;
}

// ρ c_p V, J/K.
double capacity_J_K(const Material& m, double volume_mm3) {
  return m.density_kg_m3 * m.specific_heat_J_kgK * volume_mm3 * 1e-9;
}

// Thermal diffusivity through the layers, α = k / (ρ c_p), m²/s.
double diffusivity_through_m2_s(const Material& m) {
  return m.conductivity_through_W_mK / (m.density_kg_m3 * m.specific_heat_J_kgK);
}

// No loss anywhere: no convection, no radiation (set by the material), insulated table.
Environment adiabatic() {
  Environment env;
  env.convection_W_m2K = 0.0;
  env.bed_insulated = true;
  return env;
}

// A column of `count` cells of `thickness_mm` × `area_mm2` stacked upwards from the table (z = 0), all born
// at t = 0; cell i is toolpath layer i, so the result's layer history is every cell's own history. The
// bottom cell rests on the table with its whole section; nothing is open to the air.
ThermalMesh column(int count, double thickness_mm, double area_mm2) {
  ThermalMesh mesh;
  mesh.voxel_size_mm = thickness_mm;  // only its half is used, as the least centroid distance
  for (int i = 0; i < count; ++i)
    mesh.cells.push_back(cell_at({0.0, 0.0, (i + 0.5) * thickness_mm}, area_mm2 * thickness_mm, 0.0, i));
  mesh.cells.front().table_area_mm2 = area_mm2;
  for (int i = 0; i + 1 < count; ++i)
    mesh.links.push_back(
        link(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(i + 1), {0.0, 0.0, area_mm2}));
  return mesh;
}

// ---- lumped body ----------------------------------------------------------------------------------------

// A 20 mm cube, open on five faces (100 mm² × 5), the sixth on the table: one cell, so a lumped body.
ThermalMesh open_cube() {
  ThermalMesh mesh;
  mesh.voxel_size_mm = 1.0;
  mesh.cells.push_back(cell_at({10.0, 10.0, 10.0}, 8000.0));
  mesh.cells[0].open_area_mm2 = 2000.0;
  mesh.cells[0].table_area_mm2 = 400.0;
  return mesh;
}

// Air at 18 °C cooling by convection at `h_W_m2K`; the table insulated.
Environment air_over_insulated_table(double h_W_m2K) {
  return {.ambient_c = 18.0, .bed_insulated = true, .convection_W_m2K = h_W_m2K};
}

// Newton's law of cooling of a lumped body (Incropera & DeWitt, Fundamentals of Heat and Mass Transfer,
// 6th ed., §5.1, the lumped capacitance method): T(t) = T∞ + (T0 − T∞) exp(−t/τ), τ = ρ c_p V / (h A_s). One
// cell is exactly a lumped body (one temperature), so the only error is the integrator's.
TEST(HeatLumped, OneCellCoolsExponentially) {
  const Material material = test_material();  // ε = 0: convection only
  const Environment env = air_over_insulated_table(7.0);
  const ThermalMesh mesh = open_cube();
  const double c = capacity_J_K(material, 8000.0);
  const double tau_s = c / (env.convection_W_m2K * 2000.0e-6);  // 1335 s

  HeatOptions options;
  options.cooldown_s = 3.0 * tau_s;
  options.sample_interval_s = 100.0;
  const HeatResult result = solve_heat(mesh, 1, 0.0, material, env, options);
  ASSERT_EQ(result.layer_temp_c.size(), 1u);
  ASSERT_EQ(result.sample_times_s.size(), result.layer_temp_c[0].size());
  ASSERT_GT(result.sample_times_s.size(), 30u);
  EXPECT_DOUBLE_EQ(result.start_time_s, 0.0);
  EXPECT_DOUBLE_EQ(result.end_time_s, 3.0 * tau_s);

  const double t0 = material.deposition_temp_c, ta = env.ambient_c;
  const auto exact = [&](double t) { return ta + (t0 - ta) * std::exp(-t / tau_s); };
  // The error over the initial difference T0 − T∞ (as Incropera's θ/θi), and, stricter, over the excess
  // T − T∞ still left at each time (at 3τ only 5 % of it: there the integrator's absolute tolerance of
  // 0.05 K shows).
  double worst = 0.0, worst_of_excess = 0.0;
  for (std::size_t k = 0; k < result.sample_times_s.size(); ++k) {
    const double t = result.sample_times_s[k];
    EXPECT_NEAR(t, 100.0 * static_cast<double>(k), 1e-9);
    const double error_k = std::abs(result.layer_temp_c[0][k] - exact(t));
    worst = std::max(worst, error_k / (t0 - ta));
    worst_of_excess = std::max(worst_of_excess, error_k / (exact(t) - ta));
  }
  const double final_error = std::abs(result.final_temp_c[0] - exact(3.0 * tau_s)) / (t0 - ta);
  RecordProperty("max_error_fraction", sci(worst));
  RecordProperty("max_error_of_excess", sci(worst_of_excess));
  RecordProperty("final_error_fraction", sci(final_error));
  EXPECT_LT(worst, 0.01);
  EXPECT_LT(final_error, 0.01);
  EXPECT_LT(worst_of_excess, 0.01);
  EXPECT_LT(worst, 5e-3);  // what the integrator achieves at its default tolerances (2e-3)

  // The energy lost is ∫ h A (T − T∞) dt = C (T0 − T(t_end)) analytically: checks the loss state on its own.
  const double lost_J = c * (t0 - exact(3.0 * tau_s));
  EXPECT_NEAR(result.energy_lost_J, lost_J, 0.01 * lost_J);
  EXPECT_NEAR(result.energy_in_J, c * (t0 - ta), 1e-9 * c * (t0 - ta));
}

// The part-cooling fan (HeatOptions::fan, Environment::fan_convection_W_m2K): the cube of the test above
// cools with natural convection (7 W/m²K) until the fan comes on at half its 40 W/m²K, then with max(7, 0.5 ×
// 40) = 20 W/m²K: two pieces of Newton's law of cooling, joined at the switch.
TEST(HeatLumped, TheFanCoolsWithItsForcedConvectionFromItsSetting) {
  const Material material = test_material();
  Environment env;
  env.bed_insulated = true;
  env.convection_W_m2K = 7.0;
  env.fan_convection_W_m2K = 40.0;
  ThermalMesh mesh;
  mesh.voxel_size_mm = 1.0;
  mesh.cells.push_back(cell_at({10.0, 10.0, 10.0}, 8000.0));
  mesh.cells[0].open_area_mm2 = 2000.0;
  const double c = capacity_J_K(material, 8000.0);
  const double tau_still = c / (7.0 * 2000.0e-6), tau_fan = c / (20.0 * 2000.0e-6);
  constexpr double kSwitch = 300.0;
  HeatOptions options;
  options.cooldown_s = 1500.0;
  options.sample_interval_s = 50.0;
  options.fan = {{.time_s = kSwitch, .output = 0.5}};
  const HeatResult result = solve_heat(mesh, 1, 0.0, material, env, options);
  const double t0 = material.deposition_temp_c, ta = env.ambient_c;
  const auto exact = [&](double t) {
    if (t <= kSwitch) return ta + (t0 - ta) * std::exp(-t / tau_still);
    return ta + (t0 - ta) * std::exp(-kSwitch / tau_still) * std::exp(-(t - kSwitch) / tau_fan);
  };
  double worst = 0.0;
  for (std::size_t k = 0; k < result.sample_times_s.size(); ++k)
    worst =
        std::max(worst, std::abs(result.layer_temp_c[0][k] - exact(result.sample_times_s[k])) / (t0 - ta));
  RecordProperty("max_error_fraction", sci(worst));
  EXPECT_LT(worst, 5e-3);
  // Without the fan it would end some 40 K warmer: the switch is seen.
  EXPECT_LT(result.final_temp_c[0], ta + (t0 - ta) * std::exp(-1500.0 / tau_still) - 10.0);
}

// Faces towards a cell not yet born are open surface: a cube whose neighbour is born late cools through its
// own open area and the shared face (τ₁ = C / (h (A_open + A_link))) until then. Same formula as above.
// h varying with height (Environment::convection_by_height): two separate cubes, one low and one high, each
// cools as a lumped body with the coefficient at its own height (linear between the points), and beyond the
// last point the last value holds.
TEST(HeatLumped, ConvectionVariesWithHeight) {
  const Material material = test_material();
  Environment env;
  env.bed_insulated = true;
  env.ambient_c = 18.0;
  env.convection_by_height = {{0.0, 5.0}, {1000.0, 15.0}};
  EXPECT_DOUBLE_EQ(env.convection_at(-5.0), 5.0);
  EXPECT_DOUBLE_EQ(env.convection_at(250.0), 7.5);
  EXPECT_DOUBLE_EQ(env.convection_at(2000.0), 15.0);
  ThermalMesh mesh;
  mesh.voxel_size_mm = 1.0;
  mesh.cells.push_back(cell_at({10.0, 10.0, 250.0}, 8000.0));    // h 7.5
  mesh.cells.push_back(cell_at({100.0, 10.0, 1500.0}, 8000.0));  // h 15 (beyond the last point)
  for (ThermalCell& c : mesh.cells) c.open_area_mm2 = 2000.0;
  const double c = capacity_J_K(material, 8000.0);
  HeatOptions options;
  options.cooldown_s = 1000.0;
  const HeatResult result = solve_heat(mesh, 1, 0.0, material, env, options);
  const double t0 = material.deposition_temp_c, ta = env.ambient_c;
  for (const auto& [i, h] : {std::pair{0, 7.5}, std::pair{1, 15.0}}) {
    const double exact = ta + (t0 - ta) * std::exp(-1000.0 / (c / (h * 2000.0e-6)));
    EXPECT_NEAR(result.final_temp_c[static_cast<std::size_t>(i)], exact, 0.01 * (t0 - ta)) << "cell " << i;
  }
}

// Temperature-dependent specific heat (Material::specific_heat_by_temp), c_p = a + b (T − T∞): a lumped
// body cooling by convection obeys m (a + b θ) dθ/dt = −h A θ with θ = T − T∞, so
// t(θ) = (m / hA) (a ln(θ0/θ) + b (θ0 − θ)) (separation of variables, as in Incropera & DeWitt §5.1 with a
// variable capacity). The time at which the model reaches its final θ must match that t; the energy
// stored is m ∫ c_p dT.
TEST(HeatLumped, TemperatureDependentSpecificHeat) {
  Material material = test_material();
  Environment env;
  env.bed_insulated = true;
  env.ambient_c = 18.0;
  env.convection_W_m2K = 10.0;
  const double a = 1200.0, b = 4.0;  // J/kg·K and J/kg·K² from the air's temperature
  material.specific_heat_by_temp = {{env.ambient_c, a}, {500.0, a + b * (500.0 - env.ambient_c)}};
  EXPECT_DOUBLE_EQ(material.specific_heat_at(118.0), a + b * 100.0);
  EXPECT_NEAR(material.enthalpy_J_kg(18.0, 118.0), a * 100.0 + 0.5 * b * 100.0 * 100.0, 1e-9);
  ThermalMesh mesh;
  mesh.voxel_size_mm = 1.0;
  mesh.cells.push_back(cell_at({10.0, 10.0, 10.0}, 8000.0));
  mesh.cells[0].open_area_mm2 = 2000.0;
  const double mass = material.density_kg_m3 * 8000.0e-9, ha = env.convection_W_m2K * 2000.0e-6;
  HeatOptions options;
  options.cooldown_s = 2000.0;
  const HeatResult result = solve_heat(mesh, 1, 0.0, material, env, options);
  const double theta0 = material.deposition_temp_c - env.ambient_c;
  const double theta = result.final_temp_c[0] - env.ambient_c;
  const double t = mass / ha * (a * std::log(theta0 / theta) + b * (theta0 - theta));
  RecordProperty("time_error_fraction", sci(std::abs(t - 2000.0) / 2000.0));
  EXPECT_NEAR(t, 2000.0, 0.01 * 2000.0);
  const double stored = mass * material.enthalpy_J_kg(env.ambient_c, result.final_temp_c[0]);
  EXPECT_NEAR(result.energy_stored_J, stored, 1e-6 * stored);  // final_temp_c is a float
  // With c_p varying, stored energy m H(T) is no longer linear in the state, so BDF does not keep the
  // balance exactly (as it does for a constant c_p): what is left is the integration error, of the order of
  // the relative tolerance (1e-3).
  EXPECT_LT(result.energy_balance_rel_error, 1e-2);
}

// A glass-transition step in c_p (tests/thermal/lumped_cooling.hpp): one cell cooling by convection alone
// follows the separated-variable solution. Checked as the time the solve takes to reach each sampled
// temperature against the analytic time to reach it, relative: within 1e-3 at tight tolerances (relative
// 1e-6, absolute 1e-4 K; at the defaults, relative 1e-3, the test above holds it to 1 %).
TEST(HeatLumped, SpecificHeatStepFollowsTheSeparatedVariableSolution) {
  Material material = test_material();  // ε = 0: convection only
  material.specific_heat_by_temp = glass_step_specific_heat();
  const Environment env = air_over_insulated_table(7.0);
  const ThermalMesh mesh = open_cube();
  const double mass_kg = material.density_kg_m3 * 8000.0e-9, ha_W_K = env.convection_W_m2K * 2000.0e-6;
  HeatOptions options;
  options.rel_tol = 1e-6;
  options.abs_tol_k = 1e-4;
  options.cooldown_s = 3000.0;
  options.sample_interval_s = 20.0;
  const HeatResult result = solve_heat(mesh, 1, 0.0, material, env, options);
  const double t0 = material.deposition_temp_c;
  ASSERT_LT(result.final_temp_c[0], 40.0);  // cooled through the step, to 20 K above the air
  const double worst = max_time_error_fraction(material, mass_kg, ha_W_K, env.ambient_c, t0,
                                               result.sample_times_s, result.layer_temp_c[0]);
  RecordProperty("max_time_error_fraction", sci(worst));
  EXPECT_LT(worst, 1e-3);
  EXPECT_NEAR(result.energy_in_J, mass_kg * material.enthalpy_J_kg(env.ambient_c, t0),
              1e-9 * result.energy_in_J);
}

TEST(HeatLumped, FaceTowardsAnUnbornNeighbourIsOpenSurface) {
  const Material material = test_material();
  Environment env;
  env.bed_insulated = true;
  env.convection_W_m2K = 7.0;
  ThermalMesh mesh;
  mesh.voxel_size_mm = 1.0;
  const double born_late_s = 2000.0;
  mesh.cells.push_back(cell_at({10.0, 10.0, 10.0}, 8000.0, 0.0, 0));
  mesh.cells.push_back(cell_at({10.0, 10.0, 30.0}, 8000.0, born_late_s, 1));
  mesh.cells[0].open_area_mm2 = 1600.0;  // four sides; its top is the contact with cell 1
  mesh.links.push_back(link(0, 1, {0.0, 0.0, 400.0}, true));
  // The contact face lies halfway to cell 1 (the link gives no face centre), 10 mm above cell 0's centre:
  // until cell 1 is born it loses through that half cell in series with the air, 1 / (d/k + 1/h).
  const double h_top = 1.0 / (10e-3 / material.conductivity_through_W_mK + 1.0 / env.convection_W_m2K);
  const double tau_s =
      capacity_J_K(material, 8000.0) / ((env.convection_W_m2K * 1600.0 + h_top * 400.0) * 1e-6);

  HeatOptions options;
  options.cooldown_s = 100.0;
  options.sample_interval_s = 100.0;
  options.birth_interval_s = 1.0;
  const HeatResult result = solve_heat(mesh, 2, 0.0, material, env, options);
  ASSERT_EQ(result.birth_events, 2u);
  double worst = 0.0;
  for (std::size_t k = 0; k < result.sample_times_s.size(); ++k) {
    const double t = result.sample_times_s[k];
    if (t >= born_late_s) break;
    EXPECT_TRUE(std::isnan(result.layer_temp_c[1][k])) << t;  // not born yet
    const double exact = env.ambient_c + (material.deposition_temp_c - env.ambient_c) * std::exp(-t / tau_s);
    worst = std::max(worst, std::abs(result.layer_temp_c[0][k] - exact) / (exact - env.ambient_c));
  }
  RecordProperty("max_error_of_excess", sci(worst));
  EXPECT_LT(worst, 0.01);
  // The interface's substrate temperature is the older cell's as the younger is born.
  ASSERT_EQ(result.interfaces.size(), 1u);
  const double at_birth =
      env.ambient_c + (material.deposition_temp_c - env.ambient_c) * std::exp(-born_late_s / tau_s);
  EXPECT_NEAR(result.interfaces[0].substrate_c, at_birth, 0.01 * (at_birth - env.ambient_c));
  EXPECT_TRUE(result.interfaces[0].on_top);
}

// ---- conduction ------------------------------------------------------------------------------------------

// The conduction tests resolve long columns of cells, whose slow modes the integrator must follow with large
// steps: they run at the default tolerances, as a user's scenario does. (With CVODE's default linear
// tolerance, GMRES with a diagonal preconditioner left noise of about 1 % of the temperature range in those
// modes, and the steady bar's top cell wandered by kelvins; thermal/cvode.cpp sets it tighter.)
// Semi-infinite solid whose surface is suddenly held at T_s (Carslaw & Jaeger, Conduction of Heat in Solids,
// 2nd ed., ch. II, the semi-infinite solid with constant surface temperature; Incropera & DeWitt §5.7, case
// 1): T(x, t) = T_s + (T_i − T_s) erf(x / (2 √(α t))). A column of thin cells born at the deposition
// temperature (T_i) on a table held at T_s through a contact conductance so large that its resistance (1e-6
// m²K/W) is nothing against one cell's (1.4e-3 m²K/W).
//
// The mesh puts the bed's conductance between the table and the bottom cell's mean temperature, without
// the half cell of conduction between them: the surface the model holds at T_s is the bottom cell's centre,
// half a cell above the table. Measured from the table (the physical surface, as here) that shifts the
// profile by Δz/2, an error of (Δz/2) / √(π α t) of (T_i − T_s): with 300 cells of 0.5 mm, 0.66 % at t/2
// and 0.47 % at t (√(α t) = 30 mm), which is why the column is this fine (measured: 0.66 %; from the bottom
// cell's centre 0.04 %). The far end, 5 √(α t) away, is still undisturbed.
TEST(HeatConduction, SemiInfiniteSolidWithFixedSurfaceTemperatureFollowsErf) {
  const Material material = test_material();
  Environment env = adiabatic();
  env.bed_insulated = false;
  env.bed_temp_c = 20.0;
  env.bed_contact_W_m2K = 1e6;
  constexpr int kCells = 300;
  constexpr double kDz = 0.5;
  const ThermalMesh mesh = column(kCells, kDz, 100.0);
  const double alpha = diffusivity_through_m2_s(material);
  const double penetration_mm = 30.0;                             // √(α t)
  const double t_s = std::pow(penetration_mm * 1e-3, 2) / alpha;  // 4808 s
  ASSERT_GE(kCells * kDz, 5.0 * penetration_mm);

  HeatOptions options;
  options.cooldown_s = t_s;
  options.sample_interval_s = 0.5 * t_s;  // samples at 0, t/2 and t: every cell's history (cell i is layer i)
  const HeatResult result = solve_heat(mesh, kCells, 0.0, material, env, options);
  ASSERT_EQ(result.sample_times_s.size(), 3u);

  const double ti = material.deposition_temp_c, ts = env.bed_temp_c;
  double worst = 0.0, worst_from_centre = 0.0;
  for (std::size_t k = 1; k < 3; ++k) {
    const double t = result.sample_times_s[k];
    const double two_root_alpha_t_mm = 2.0 * std::sqrt(alpha * t) * 1e3;
    for (int i = 0; i < kCells; ++i) {
      const double temp = result.layer_temp_c[static_cast<std::size_t>(i)][k];
      const double x_mm = (i + 0.5) * kDz;  // the cell's centre above the table
      const double exact = ts + (ti - ts) * std::erf(x_mm / two_root_alpha_t_mm);
      worst = std::max(worst, std::abs(temp - exact) / (ti - ts));
      // The same measured from the bottom cell's centre, where the model holds T_s (for the report only).
      const double exact_from_centre = ts + (ti - ts) * std::erf(i * kDz / two_root_alpha_t_mm);
      worst_from_centre = std::max(worst_from_centre, std::abs(temp - exact_from_centre) / (ti - ts));
    }
  }
  RecordProperty("max_error_fraction", sci(worst));
  RecordProperty("max_error_fraction_from_bottom_cell_centre", sci(worst_from_centre));
  EXPECT_LT(worst, 0.01);
  // The far end has not felt the surface yet: the column is semi-infinite for this time.
  EXPECT_NEAR(result.final_temp_c.back(), ti, 1e-3 * (ti - ts));
  // The history samples and the final temperatures agree.
  for (int i = 0; i < kCells; ++i)
    EXPECT_FLOAT_EQ(result.layer_temp_c[static_cast<std::size_t>(i)][2],
                    result.final_temp_c[static_cast<std::size_t>(i)]);
}

// Steady conduction through a plane wall between the table and the air: a thermal circuit of resistances in
// series (Incropera & DeWitt §3.1, the plane wall and thermal resistance): q'' = (T_bed − T∞) / (1/h_bed +
// L/k + 1/h), and inside the wall T(z) = T_bed − q'' (1/h_bed + z/k), linear. A column of 50 cells of 1 mm,
// cooled from 200 °C for long enough (18 times the slowest time constant, at most L²/α + C/(hA) ≈ 2.7e4 s,
// leaves 1e-6 K of the start) that only the steady profile is left. Radiation off.
//
// The reference is the continuous wall, 1/h_bed + L/k + 1/h in series (Incropera & DeWitt §3.1, the plane
// wall with convection on both sides): the half cells between the end cells' centres and the table and the
// air (ThermalCell::open_depth_mm3, the table under the centroid) put the cells' centres exactly on its
// linear profile, so only the integrator's tolerance is left (the bound: 0.05 % of the drop).
TEST(HeatConduction, SteadyBarBetweenTableAndAirIsLinear) {
  const Material material = test_material();
  Environment env;
  env.bed_temp_c = 65.0;
  env.bed_contact_W_m2K = 100.0;
  env.ambient_c = 18.0;
  env.convection_W_m2K = 7.0;
  constexpr int kCells = 50;
  constexpr double kDz = 1.0;
  constexpr double kArea = 100.0;
  ThermalMesh mesh = column(kCells, kDz, kArea);
  mesh.cells.back().open_area_mm2 = kArea;  // the top face only: the sides are insulated
  mesh.cells.back().open_depth_mm3 = {0.0, 0.0, kArea * 0.5 * kDz};

  HeatOptions options;
  options.cooldown_s = 5e5;
  options.sample_interval_s = 1e5;
  const HeatResult result = solve_heat(mesh, kCells, 0.0, material, env, options);

  const double k = material.conductivity_through_W_mK;
  const double dz_m = kDz * 1e-3;
  const double r_bed = 1.0 / env.bed_contact_W_m2K, r_top = 1.0 / env.convection_W_m2K;  // m²K/W
  const double drop = env.bed_temp_c - env.ambient_c;
  const double q_wall = drop / (r_bed + kCells * dz_m / k + r_top);
  double worst_wall = 0.0;
  for (int i = 0; i < kCells; ++i) {
    const double temp = result.final_temp_c[static_cast<std::size_t>(i)];
    const double wall = env.bed_temp_c - q_wall * (r_bed + (i + 0.5) * dz_m / k);
    worst_wall = std::max(worst_wall, std::abs(temp - wall) / drop);
  }
  RecordProperty("max_error_fraction_wall", sci(worst_wall));
  EXPECT_LT(worst_wall, 5e-4);
}

// The table's heat flux under a single layer, at steady state: one cell (a 4 mm layer, 100 mm² of it) on a
// 65 °C table through its contact, its top open to 18 °C air, its sides insulated, radiation on. The series
// solution is q = (T_bed − T_s)/(1/h_bed + h/k) = h (T_s − T∞) + ε σ (T_s⁴ − T∞⁴) with T_s its top face,
// solved here by bisection. The model's flux, through its table conductance from the cell's steady
// temperature, is within 2 % of it (the half cells are h/2k = 0.0057 m²K/W each side, against 1/h_bed =
// 0.01).
TEST(HeatConduction, TableFluxUnderOneLayerFollowsTheSeriesSolution) {
  Material material = test_material();
  material.emissivity = 0.85;
  Environment env;
  env.bed_temp_c = 65.0;
  env.bed_contact_W_m2K = 100.0;
  env.ambient_c = 18.0;
  env.convection_W_m2K = 7.0;
  constexpr double kH = 4.0, kArea = 100.0;
  ThermalMesh mesh = column(1, kH, kArea);
  mesh.cells[0].open_area_mm2 = kArea;
  mesh.cells[0].open_depth_mm3 = {0.0, 0.0, kArea * 0.5 * kH};
  HeatOptions options;
  options.cooldown_s = 2e4;  // C/(G) is about 200 s
  options.sample_interval_s = 1e3;
  const HeatResult result = solve_heat(mesh, 1, 0.0, material, env, options);

  const double k = material.conductivity_through_W_mK;
  const double r_below = 1.0 / env.bed_contact_W_m2K + kH * 1e-3 / k;
  const double es = material.emissivity * kStefanBoltzmann_W_m2K4;
  const auto balance = [&](double ts) {  // what reaches the top face less what leaves it, W/m²
    const double tk = ts + kKelvinOffset, ak = env.ambient_c + kKelvinOffset;
    return (env.bed_temp_c - ts) / r_below - env.convection_W_m2K * (ts - env.ambient_c) -
           es * (tk * tk * tk * tk - ak * ak * ak * ak);
  };
  double lo = env.ambient_c, hi = env.bed_temp_c;
  for (int i = 0; i < 100; ++i) (balance(0.5 * (lo + hi)) > 0.0 ? lo : hi) = 0.5 * (lo + hi);
  const double ts = 0.5 * (lo + hi);
  const double q_series = (env.bed_temp_c - ts) / r_below;
  const double t_cell = result.final_temp_c[0];
  const double q_model = (env.bed_temp_c - t_cell) / (1.0 / env.bed_contact_W_m2K + 0.5 * kH * 1e-3 / k);
  RecordProperty("table_flux_error", sci(q_model / q_series - 1.0));
  EXPECT_NEAR(q_model / q_series, 1.0, 0.02);
  // The cell sits halfway between the table's side and the top face on the series profile.
  EXPECT_NEAR(t_cell, ts + q_series * 0.5 * kH * 1e-3 / k, 0.05);
}

// ---- orthotropy ------------------------------------------------------------------------------------------

// The conductance of one contact, measured at steady state: cell 0 held at T_bed by a huge contact
// conductance, cell 1 open to the air; in steady state G (T0 − T1) = h A (T1 − T∞) (the same series circuit
// as above), so G = h A (T1 − T∞) / (T0 − T1). `along0`, `along1`: the two cells' bead directions;
// `normal`: the contact's direction.
double measured_conductance_W_K(const Eigen::Vector2d& along0, const Eigen::Vector2d& along1,
                                const Eigen::Vector3d& normal) {
  const Material material = test_material();
  Environment env;
  env.bed_temp_c = 100.0;
  env.bed_contact_W_m2K = 1e6;
  env.ambient_c = 20.0;
  env.convection_W_m2K = 25.0;
  ThermalMesh mesh;
  mesh.voxel_size_mm = 1.0;
  // Two 10 mm cubes side by side along `normal`.
  mesh.cells.push_back(cell_at({0.0, 0.0, 5.0}, 1000.0));
  mesh.cells.push_back(cell_at(Eigen::Vector3d(0.0, 0.0, 5.0) + 10.0 * normal, 1000.0));
  mesh.cells[0].along = along0;
  mesh.cells[1].along = along1;
  mesh.cells[0].table_area_mm2 = 100.0;
  mesh.cells[1].open_area_mm2 = 400.0;
  mesh.links.push_back(link(0, 1, 100.0 * normal));
  HeatOptions options;
  options.cooldown_s = 1e5;  // 1000 times C / (G + hA) ≈ 100 s
  const HeatResult result = solve_heat(mesh, 1, 0.0, material, env, options);
  const double t0 = result.final_temp_c[0], t1 = result.final_temp_c[1];
  return env.convection_W_m2K * 400e-6 * (t1 - env.ambient_c) / (t0 - t1);
}

// G = k_n A / d with k_n = nᵀ K n (docs: thermal/heat.hpp): a contact across the bead's direction conducts
// with k_across, one along it with k_along, one between layers with k_through; a contact between cells of
// crossing beads with the mean of the two tensors. Reference: Fourier's law in an anisotropic solid, the
// heat flux along n being −nᵀ K ∇T (Carslaw & Jaeger ch. I, anisotropic solids). Measured: 1.5e-4 on the
// ratio.
TEST(HeatOrthotropy, ContactConductanceUsesTheConductivityAlongItsNormal) {
  const Material m = test_material();
  const Eigen::Vector2d x = Eigen::Vector2d::UnitX(), y = Eigen::Vector2d::UnitY();
  const Eigen::Vector3d nx = Eigen::Vector3d::UnitX(), nz = Eigen::Vector3d::UnitZ();
  const double per_k = 100e-6 / 10e-3;                        // A / d, m
  const double along = measured_conductance_W_K(x, x, nx);    // beads along x, contact along x
  const double across = measured_conductance_W_K(y, y, nx);   // beads along y, contact along x
  const double through = measured_conductance_W_K(x, x, nz);  // stacked
  const double crossing = measured_conductance_W_K(x, y, nx);
  const auto error = [](double value, double reference) { return std::abs(value - reference) / reference; };
  RecordProperty("along_error", sci(error(along, m.conductivity_along_W_mK * per_k)));
  RecordProperty("across_error", sci(error(across, m.conductivity_across_W_mK * per_k)));
  RecordProperty("ratio_error",
                 sci(error(along / across, m.conductivity_along_W_mK / m.conductivity_across_W_mK)));
  EXPECT_LT(error(along / across, m.conductivity_along_W_mK / m.conductivity_across_W_mK), 0.01);
  EXPECT_LT(error(along, m.conductivity_along_W_mK * per_k), 0.01);
  EXPECT_LT(error(across, m.conductivity_across_W_mK * per_k), 0.01);
  EXPECT_LT(error(through, m.conductivity_through_W_mK * per_k), 0.01);
  EXPECT_LT(error(crossing, 0.5 * (m.conductivity_along_W_mK + m.conductivity_across_W_mK) * per_k), 0.01);
  // The sign of the bead's direction means nothing.
  EXPECT_LT(error(measured_conductance_W_K(-x, x, nx), along), 1e-6);
}

// ---- energy ----------------------------------------------------------------------------------------------

// A wall of 12 cells, 100 × 20 × 5 mm each, born one every 30 s on a table at 65 °C, with convection and
// radiation (ε = 0.85) on the sides and faces towards unborn cells, then 600 s of cooldown. Energy brought
// in − lost − stored must vanish; the loss is integrated as its own state, so this checks the bookkeeping.
// Measured at the default tolerances: 1.0e-4 of the energy brought in. BDF keeps this linear invariant up to
// how exactly each step's linear systems are solved: it is the GMRES iteration's residual (CVODE's default
// linear tolerance) that is left; a linear tolerance 50 times tighter closes it to 2e-7.
TEST(HeatEnergy, BalanceClosesWithBirthsRadiationAndAHeatedBed) {
  Material material = test_material();
  material.emissivity = 0.85;
  const Environment env;  // 18 °C air, 7 W/m²K, table at 65 °C through 100 W/m²K
  ThermalMesh mesh;
  mesh.voxel_size_mm = 1.0;
  constexpr int kCells = 12;
  const double volume = 100.0 * 20.0 * 5.0, section = 100.0 * 20.0, sides = 2.0 * (100.0 + 20.0) * 5.0;
  for (int i = 0; i < kCells; ++i) {
    mesh.cells.push_back(cell_at({50.0, 10.0, (i + 0.5) * 5.0}, volume, 30.0 * i, i));
    mesh.cells.back().open_area_mm2 = sides;
  }
  mesh.cells.front().table_area_mm2 = section;
  mesh.cells.back().open_area_mm2 += section;
  for (int i = 0; i + 1 < kCells; ++i)
    mesh.links.push_back(
        link(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(i + 1), {0.0, 0.0, section}, true));
  HeatOptions options;
  options.birth_interval_s = 1.0;
  const HeatResult result = solve_heat(mesh, kCells, 30.0 * (kCells - 1), material, env, options);
  EXPECT_EQ(result.birth_events, static_cast<std::size_t>(kCells));
  RecordProperty("energy_balance_rel_error", sci(result.energy_balance_rel_error));
  EXPECT_LT(result.energy_balance_rel_error, 1e-3);

  // The three terms by hand: in from the births, stored from the final temperatures.
  const double c = capacity_J_K(material, volume);
  const double in_J = kCells * c * (material.deposition_temp_c - env.ambient_c);
  EXPECT_NEAR(result.energy_in_J, in_J, 1e-9 * in_J);
  double stored_J = 0.0;
  for (float t : result.final_temp_c) stored_J += c * (t - env.ambient_c);
  EXPECT_NEAR(result.energy_stored_J, stored_J, 1e-6 * in_J);
  EXPECT_GT(result.energy_lost_J, 0.3 * in_J);
  EXPECT_LT(result.energy_lost_J, in_J);
}

TEST(HeatBirths, AnAutomaticIntervalIsMadeLongerWhenThePrintWouldNeedTooManyEvents) {
  // Twelve stacked cells born 30 s apart (330 s). The automatic interval (a fifth of C/ΣG, under 30 s for
  // these cells) is used as it is when few events follow: twelve. Allowed 3 events, it becomes 330 / 3 =
  // 110 s, and the twelve cells are born in 3 groups (0-90, 120-210, 240-330 s).
  const Material material = test_material();
  const Environment env;
  ThermalMesh mesh;
  mesh.voxel_size_mm = 1.0;
  constexpr int kCells = 12;
  const double section = 100.0 * 20.0;
  for (int i = 0; i < kCells; ++i)
    mesh.cells.push_back(cell_at({50.0, 10.0, (i + 0.5) * 5.0}, 1e4, 30.0 * i, i));
  for (int i = 0; i + 1 < kCells; ++i)
    mesh.links.push_back(
        link(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(i + 1), {0.0, 0.0, section}, true));
  HeatOptions options;
  options.cooldown_s = 10.0;
  const HeatResult free = solve_heat(mesh, kCells, 330.0, material, env, options);
  EXPECT_EQ(free.birth_interval_s, free.automatic_interval_s);
  ASSERT_LT(free.automatic_interval_s, 30.0) << "the cap would not be what lengthens the interval";
  EXPECT_EQ(free.birth_events, static_cast<std::size_t>(kCells));
  options.max_automatic_birth_events = 3;
  const HeatResult capped = solve_heat(mesh, kCells, 330.0, material, env, options);
  EXPECT_DOUBLE_EQ(capped.birth_interval_s, 110.0);
  EXPECT_LE(capped.birth_events, 3u);
  options.birth_interval_s = 1.0;  // asked for: kept
  const HeatResult asked = solve_heat(mesh, kCells, 330.0, material, env, options);
  EXPECT_EQ(asked.birth_interval_s, 1.0);
  EXPECT_EQ(asked.birth_events, static_cast<std::size_t>(kCells));
}

// ---- healing ---------------------------------------------------------------------------------------------

// An isothermal interface (Yang & Pitchumani 2002, eq. for D_h; at constant temperature it reduces to the
// isothermal reptation result D_h = (t / t_w)^(1/4), Wool & O'Connor 1981): two cubes, the upper born 10 s
// after the lower, nothing lost anywhere (no convection, no radiation, insulated table), both at a
// deposition temperature of 150 °C for good. The interface heals from the younger's birth (10 s) to the end
// (40 s): D_h = (30 s / t_w(150 °C))^(1/4). It is still warm then: healing is followed no further than the
// cooldown (max_cooldown_s 0), and the interface is reported as still warm.
TEST(HeatHealing, IsothermalInterfaceHealsAsTheFourthRootOfTime) {
  for (const HealingLaw law : {HealingLaw::kWlf, HealingLaw::kArrhenius}) {
    SCOPED_TRACE(name_of(law));
    Material material = test_material();
    material.healing_law = law;
    material.deposition_temp_c = 150.0;
    material.glass_transition_c = 110.0;
    material.healing_ref_temp_c = 200.0;
    material.reptation_time_ref_s = 1.0;
    material.healing_activation_J_mol = 150e3;
    material.healing_min_temp_c = 110.0;
    // A melt as runny as oil at 200 °C (1 Pa·s, a test value): the substrate, soft at 150 °C, slumps.
    material.viscosity_ref_Pa_s = 1.0;
    ThermalMesh mesh;
    mesh.voxel_size_mm = 1.0;
    mesh.cells.push_back(cell_at({5.0, 5.0, 5.0}, 1000.0, 0.0, 0));
    mesh.cells.back().table_area_mm2 = 100.0;  // on the (insulated) table
    mesh.cells.push_back(cell_at({5.0, 5.0, 15.0}, 1000.0, 10.0, 1));
    mesh.links.push_back(link(0, 1, {0.0, 0.0, 100.0}, true));
    HeatOptions options;
    options.birth_interval_s = 0.5;  // the default (a fifth of C/G ≈ 106 s) would merge the two births
    options.cooldown_s = 30.0;
    options.max_cooldown_s = 0.0;
    const HeatResult result = solve_heat(mesh, 2, 0.0, material, adiabatic(), options);

    // By hand, WLF: log10 t_w(150 °C) / t_w(200 °C) = 17.44 · 90/141.6 − 17.44 · 40/91.6 = 3.4690253, so
    // t_w = 2944.593 s. Arrhenius: 150000 / 8.314462618 · (1/423.15 − 1/473.15) = 4.5054055, exp(4.5054055)
    // = 90.50504 s.
    const double t_w = law == HealingLaw::kWlf ? std::pow(10.0, 3.4690253) : 90.50504;
    const double expected = std::min(1.0, std::pow(30.0 / t_w, 0.25));  // 0.3177 (WLF), 0.7588 (Arrhenius)
    ASSERT_EQ(result.interfaces.size(), 1u);
    const InterfaceResult& r = result.interfaces[0];
    RecordProperty("healing_error", sci(std::abs(r.healing - expected) / expected));
    EXPECT_NEAR(r.healing, expected, 1e-6 * expected);  // constant rate: the quadrature is exact
    // Nothing moved.
    EXPECT_FLOAT_EQ(result.final_temp_c[0], 150.0f);
    EXPECT_FLOAT_EQ(result.final_temp_c[1], 150.0f);
    // It landed on top of a substrate at 150 °C, all of it soft (10 mm), which slumped: too hot wins.
    EXPECT_TRUE(r.on_top);
    EXPECT_DOUBLE_EQ(r.substrate_c, 150.0);
    EXPECT_DOUBLE_EQ(r.support.soft_height_mm, 10.0);
    EXPECT_GT(r.support.slump_mm, r.support.allowed_mm);
    EXPECT_EQ(r.verdict, Verdict::kTooHot);
    EXPECT_EQ(result.energy_lost_J, 0.0);
    // Still at 150 °C when healing stopped with the cooldown.
    EXPECT_TRUE(r.still_warm);
    EXPECT_EQ(result.still_warm, 1u);
    EXPECT_DOUBLE_EQ(result.still_warm_area_mm2, 100.0);
    EXPECT_DOUBLE_EQ(result.healing_end_s, result.end_time_s);
    ASSERT_FALSE(result.notes.empty());
    EXPECT_NE(result.notes.back().find("thermal.max_cooldown"), std::string::npos) << result.notes.back();
  }
}

// Healing saturates at 1 once ∫ dt / t_w reaches 1: at the reference temperature t_w = t_ref = 1 s.
TEST(HeatHealing, HealingSaturatesAtOne) {
  Material material = test_material();
  material.deposition_temp_c = material.healing_ref_temp_c;
  ThermalMesh mesh;
  mesh.voxel_size_mm = 1.0;
  mesh.cells.push_back(cell_at({5.0, 5.0, 5.0}, 1000.0));
  mesh.cells.push_back(cell_at({15.0, 5.0, 5.0}, 1000.0));
  mesh.links.push_back(link(0, 1, {100.0, 0.0, 0.0}, true));
  HeatOptions options;
  options.cooldown_s = 10.0;
  options.max_cooldown_s = 10.0;  // adiabatic: it would stay warm for ever
  const HeatResult result = solve_heat(mesh, 1, 0.0, material, adiabatic(), options);
  ASSERT_EQ(result.interfaces.size(), 1u);
  EXPECT_DOUBLE_EQ(result.interfaces[0].healing, 1.0);
  EXPECT_FALSE(result.interfaces[0].on_top);  // side by side
  EXPECT_EQ(result.interfaces[0].verdict, Verdict::kOk);
}

// Healing is followed until every interface has cooled below the healing threshold, so how long the
// cooldown is does not move it: a small block (3 x 3 cells, 4 layers) on an insulated table in still air
// (2 W/m²K, no radiation), healing slowly enough (t_w 1000 s at 200 °C) not to reach 1, is still warm 10
// minutes after its last layer, and its interfaces' healing differs by less than 0.005 between a cooldown
// of 10 and one of 60 minutes, under either law (5e-7 under WLF, 5e-6 under Arrhenius). Stopped at 10
// minutes instead (max_cooldown_s), the warm interfaces are reported, and the healing they miss is 6e-4
// under WLF and 7e-3 under the Arrhenius law, which heals near T_g.
TEST(HeatHealing, HealingDoesNotDependOnTheCooldownOnceEveryInterfaceHasCooled) {
  const ThermalMesh mesh = block(3, 3, 4);
  Environment env;
  env.convection_W_m2K = 2.0;
  env.bed_insulated = true;
  for (const HealingLaw law : {HealingLaw::kWlf, HealingLaw::kArrhenius}) {
    SCOPED_TRACE(name_of(law));
    Material material = test_material();
    material.healing_law = law;
    material.reptation_time_ref_s = 1000.0;
    HeatOptions options;
    options.cooldown_s = 600.0;
    const HeatResult short_cooldown = solve_heat(mesh, 4, 0.0, material, env, options);
    options.cooldown_s = 3600.0;
    const HeatResult long_cooldown = solve_heat(mesh, 4, 0.0, material, env, options);
    options.cooldown_s = 600.0;
    options.max_cooldown_s = 600.0;
    const HeatResult stopped = solve_heat(mesh, 4, 0.0, material, env, options);

    // The block was still warm at the end of the short cooldown: healing went on past it.
    EXPECT_GT(short_cooldown.healing_end_s, short_cooldown.end_time_s + 60.0);
    EXPECT_EQ(short_cooldown.still_warm, 0u);
    EXPECT_EQ(long_cooldown.still_warm, 0u);
    ASSERT_EQ(short_cooldown.interfaces.size(), long_cooldown.interfaces.size());
    double worst = 0.0, worst_stopped = 0.0, least = 1.0;
    for (std::size_t k = 0; k < short_cooldown.interfaces.size(); ++k) {
      const double healing = long_cooldown.interfaces[k].healing;
      least = std::min(least, healing);
      worst = std::max(worst, std::abs(short_cooldown.interfaces[k].healing - healing));
      worst_stopped = std::max(worst_stopped, std::abs(stopped.interfaces[k].healing - healing));
    }
    const std::string law_name(name_of(law));
    RecordProperty("max_healing_change_" + law_name, sci(worst));
    RecordProperty("max_healing_change_stopped_at_cooldown_" + law_name, sci(worst_stopped));
    EXPECT_LT(least, 0.9);  // not all saturated: a change would show
    EXPECT_LT(worst, 0.005);
    EXPECT_GT(stopped.still_warm, 0u);
    EXPECT_GT(stopped.still_warm_area_mm2, 0.0);
    EXPECT_DOUBLE_EQ(stopped.healing_end_s, stopped.end_time_s);
    if (law == HealingLaw::kArrhenius) {
      EXPECT_GT(worst_stopped, 0.005);
    }
  }
}

// ---- options ---------------------------------------------------------------------------------------------

TEST(HeatInput, BadOptionsNameTheirKey) {
  const ThermalMesh mesh = column(2, 1.0, 1.0);
  const auto key_of = [&](const HeatOptions& o) -> std::string {
    try {
      solve_heat(mesh, 2, 0.0, test_material(), Environment{}, o);
    } catch (const InputError& e) {
      return e.key();
    }
    return "(no error)";
  };
  HeatOptions o;
  o.rel_tol = 0.0;
  EXPECT_EQ(key_of(o), "thermal.rel_tol");
  o = {};
  o.cooldown_s = -1.0;
  EXPECT_EQ(key_of(o), "thermal.cooldown");
  o = {};
  o.sample_interval_s = 0.0;
  EXPECT_EQ(key_of(o), "thermal.sample_interval");
  o = {};
  o.birth_interval_s = -1.0;
  EXPECT_EQ(key_of(o), "thermal.birth_interval");
  o = {};
  o.lump_depth = 0;
  EXPECT_EQ(key_of(o), "thermal.lump_depth");
  o = {};
  o.lump_tolerance_k = -0.1;
  EXPECT_EQ(key_of(o), "thermal.lump_tolerance");
  o = {};
  o.lump_slice_beads = 0;
  EXPECT_EQ(key_of(o), "thermal.lump_slice_beads");
}

TEST(HeatInput, EmptyMeshGivesAnEmptyResult) {
  const HeatResult result = solve_heat(ThermalMesh{}, 0, 0.0, test_material(), Environment{});
  EXPECT_TRUE(result.final_temp_c.empty());
  EXPECT_TRUE(result.interfaces.empty());
}

// ---- threads ---------------------------------------------------------------------------------------------

// The same result, to the last bit, on 1 and 2 threads, as every result must be. The block is large enough
// (18,000 cells) that the model's loops and the vector operations of thermal/vector_ops.hpp both split into
// parallel blocks; radiation on, so the right-hand side is nonlinear.
TEST(HeatThreads, SameResultOnOneAndTwoThreads) {
  constexpr int kLayers = 20;
  const ThermalMesh mesh = block(30, 30, kLayers);
  const auto [material, env, options] = block_print();
  const auto run = [&](int threads) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return solve_heat(mesh, kLayers, 0.0, material, env, options);
  };
  const HeatResult one = run(1);
  const HeatResult two = run(2);
  ASSERT_EQ(one.final_temp_c.size(), mesh.cells.size());
  EXPECT_EQ(one.steps, two.steps);
  EXPECT_EQ(one.linear_iterations, two.linear_iterations);
  EXPECT_EQ(one.final_temp_c, two.final_temp_c);
  EXPECT_EQ(one.energy_lost_J, two.energy_lost_J);
  ASSERT_EQ(one.interfaces.size(), two.interfaces.size());
  for (std::size_t k = 0; k < one.interfaces.size(); ++k) {
    EXPECT_EQ(one.interfaces[k].substrate_c, two.interfaces[k].substrate_c) << k;
    EXPECT_EQ(one.interfaces[k].healing_integral, two.interfaces[k].healing_integral) << k;
  }
  // Not a trivial run: the part heated and cooled, and the top is well below the deposition temperature.
  EXPECT_LT(one.final_temp_c.back(), material.deposition_temp_c - 50.0);
  EXPECT_GT(one.steps, 100);
}

// ---- settled cells ---------------------------------------------------------------------------------------

TEST(HeatSettled, LumpedLayersFarBelowTheTopGiveTheSameInterfacesWithinTheSolversTolerance) {
  const ThermalMesh mesh = thin_wall();
  const auto [material, env, options] = thin_wall_print();
  const double end_s = mesh.cells.back().birth_s;
  HeatOptions kept = options;
  kept.lump = false;
  const HeatResult full = solve_heat(mesh, 40, end_s, material, env, kept);
  const HeatResult lumped = solve_heat(mesh, 40, end_s, material, env, options);
  HeatOptions tight = kept;  // how far the solver's own tolerance moves the answer
  tight.rel_tol = 1e-4;
  tight.abs_tol_k = 0.005;
  const HeatResult reference = solve_heat(mesh, 40, end_s, material, env, tight);

  EXPECT_EQ(full.lumped_cells, 0u);
  EXPECT_EQ(full.model_cells, mesh.cells.size());
  EXPECT_GT(lumped.lump_events, 0u);
  EXPECT_GT(lumped.lumped_cells, mesh.cells.size() / 2) << "the lower layers should have settled";
  EXPECT_LT(lumped.model_cells, mesh.cells.size() / 2);
  const auto lump_note = [](const HeatResult& r) {
    return std::count_if(r.notes.begin(), r.notes.end(),
                         [](const std::string& note) { return note.find("lumped") != std::string::npos; });
  };
  EXPECT_EQ(lump_note(lumped), 1);
  EXPECT_EQ(lump_note(full), 0);
  // Lumping keeps the enthalpy: the balance closes as well as without it.
  RecordProperty("balance_full", sci(full.energy_balance_rel_error));
  RecordProperty("balance_lumped", sci(lumped.energy_balance_rel_error));
  EXPECT_LT(lumped.energy_balance_rel_error, 1e-3);
  EXPECT_LE(lumped.energy_balance_rel_error, 2.0 * full.energy_balance_rel_error);
  EXPECT_NEAR(lumped.energy_in_J, full.energy_in_J, 1e-12 * full.energy_in_J);

  const auto worst = [](const HeatResult& a, const HeatResult& b, auto field) {
    double d = 0.0;
    for (std::size_t k = 0; k < a.interfaces.size(); ++k)
      d = std::max(d, std::abs(field(a.interfaces[k]) - field(b.interfaces[k])));
    return d;
  };
  const auto substrate = [](const InterfaceResult& r) { return r.substrate_c; };
  const auto healing = [](const InterfaceResult& r) { return r.healing; };
  const double tolerance_substrate = worst(full, reference, substrate);
  const double tolerance_healing = worst(full, reference, healing);
  RecordProperty("substrate_K_tolerance", sci(tolerance_substrate));
  RecordProperty("substrate_K_lumped", sci(worst(full, lumped, substrate)));
  RecordProperty("healing_tolerance", sci(tolerance_healing));
  RecordProperty("healing_lumped", sci(worst(full, lumped, healing)));
  EXPECT_LE(worst(full, lumped, substrate), std::max(tolerance_substrate, 0.1));
  EXPECT_LE(worst(full, lumped, healing), std::max(tolerance_healing, 1e-3));
  // The layers' histories and the final temperatures: a lumped cell holds its run at one temperature.
  double history = 0.0;
  for (std::size_t l = 0; l < full.layer_temp_c.size(); ++l)
    for (std::size_t s = 0; s < full.layer_temp_c[l].size(); ++s)
      if (!std::isnan(full.layer_temp_c[l][s]))
        history = std::max(
            history, static_cast<double>(std::abs(full.layer_temp_c[l][s] - lumped.layer_temp_c[l][s])));
  RecordProperty("history_K_lumped", sci(history));
  EXPECT_LT(history, 0.5);
  for (std::size_t i = 0; i < mesh.cells.size(); ++i)
    EXPECT_NEAR(lumped.final_temp_c[i], full.final_temp_c[i], 1.0) << i;
}

TEST(HeatSettled, NothingIsLumpedNearTheTop) {
  // The same wall with lump_depth beyond its height: no cell is far enough below the top.
  const ThermalMesh mesh = thin_wall();
  HeatOptions options;
  options.cooldown_s = 10.0;
  options.lump_check_cells = 80;
  options.lump_depth = 45;
  const HeatResult r =
      solve_heat(mesh, 40, mesh.cells.back().birth_s, test_material(), Environment{}, options);
  EXPECT_EQ(r.lump_events, 0u);
  EXPECT_EQ(r.model_cells, mesh.cells.size());
  for (const std::string& note : r.notes) EXPECT_EQ(note.find("lumped"), std::string::npos) << note;
}

}  // namespace
}  // namespace beadtwin::thermal
