// The bands of the verdicts over the inputs' plausible ranges (thermal/uncertainty.hpp): the moments of the
// spreads, the exact scaling of healing with the reptation time, a lumped body's substrate temperature
// against its convection coefficient, and the linearised band against brute-force sampling.
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "test_meshes.hpp"
#include "thermal/summary.hpp"
#include "thermal/uncertainty.hpp"

namespace beadtwin::thermal {
namespace {

InputRange uniform(const char* key, double lo, double hi, bool scale = false) {
  return {.key = key, .spread = Spread::kUniform, .lo = lo, .hi = hi, .scale = scale};
}

TEST(Uncertainty, MomentsOfTheSpreads) {
  const Moments u = moments_of(uniform("emissivity", 0.8, 0.95), 0.85);
  EXPECT_DOUBLE_EQ(u.mean, 0.875);
  EXPECT_NEAR(u.sd, 0.15 / std::sqrt(12.0), 1e-15);
  const Moments s = moments_of(uniform("conductivity", 0.8, 1.2, true), 0.5);  // factors on 0.5
  EXPECT_NEAR(s.mean, 0.5, 1e-15);
  EXPECT_NEAR(s.sd, 0.2 / std::sqrt(12.0), 1e-15);
  // Log-uniform on [1, e]: density 1/x, mean e − 1, second moment (e² − 1) / 2.
  const Moments l =
      moments_of({.key = "t", .spread = Spread::kLogUniform, .lo = 1.0, .hi = std::exp(1.0)}, 2.0);
  EXPECT_NEAR(l.mean, std::exp(1.0) - 1.0, 1e-12);
  EXPECT_NEAR(l.sd * l.sd, 0.5 * (std::exp(2.0) - 1.0) - l.mean * l.mean, 1e-12);
  const Moments n = moments_of({.key = "t", .spread = Spread::kNormal, .sigma = 4.0}, 200.0);
  EXPECT_DOUBLE_EQ(n.mean, 200.0);
  EXPECT_DOUBLE_EQ(n.sd, 4.0);
}

// D_h = (∫ dt / t_w)^¼ and t_w ∝ t_ref: D_h scales exactly as t_ref^(-1/4), so a log-uniform t_ref over two
// decades about its value gives D_h · exp(∓ z σ / 4), σ = ln 100 / √12, at P10 and P90 (below the cap).
TEST(Uncertainty, HealingScalesAsTheReptationTimeToTheMinusQuarter) {
  Material m = test_material();
  m.reptation_time_ref_s = 2.0;
  m.ranges = {{.key = "fusion.reptation_time", .spread = Spread::kLogUniform, .lo = 0.2, .hi = 20.0}};
  const UncertaintyPlan plan = plan_uncertainty(m, Environment{}, false);
  EXPECT_TRUE(plan.heat.empty());
  EXPECT_TRUE(plan.laws.empty());
  const double sigma = std::log(100.0) / std::sqrt(12.0);
  EXPECT_NEAR(plan.log_reptation_time.mean, 0.0, 1e-15);
  EXPECT_NEAR(plan.log_reptation_time.sd, sigma, 1e-15);

  InterfaceResult r;
  r.healing_integral = 0.05;
  r.healing = std::pow(0.05, 0.25);
  BandSum sum(r);
  sum.add_log_integral(-plan.log_reptation_time.mean, plan.log_reptation_time.sd);
  sum.finish(plan, m, Reptation(m), r);
  EXPECT_NEAR(r.healing_p10, r.healing * std::exp(-kZ90 * sigma / 4.0), 1e-12);
  EXPECT_NEAR(r.healing_p90, std::min(1.0, r.healing * std::exp(kZ90 * sigma / 4.0)), 1e-12);
  // 0.47 at the value, 0.33-0.68 across the band: below 0.9 throughout, too cold at both ends.
  EXPECT_EQ(r.verdict_cold, Verdict::kTooCold);
  EXPECT_EQ(r.verdict_hot, Verdict::kTooCold);
  EXPECT_FALSE(r.marginal());

  // Near the requirement the band crosses it: marginal, too cold only at the cold end.
  r.healing_integral = std::pow(0.9, 4.0);
  BandSum near(r);
  near.add_log_integral(0.0, sigma);
  near.finish(plan, m, Reptation(m), r);
  EXPECT_EQ(r.verdict_cold, Verdict::kTooCold);
  EXPECT_EQ(r.verdict_hot, Verdict::kOk);
  EXPECT_TRUE(r.marginal());
  EXPECT_DOUBLE_EQ(r.healing_p90, 1.0);  // capped: the P90 of min(1, D_h) is min(1, P90 of D_h)
}

// Two cubes of 10 mm, the second born on the first at 120 s, with a conductivity so high that each is at one
// temperature, losing by convection alone (no radiation, no table).
ThermalMesh two_cubes() {
  ThermalMesh mesh;
  mesh.voxel_size_mm = 1.0;
  ThermalCell lower = cell_at({5, 5, 5}, 1000.0, 0.0, 0);
  lower.open_area_mm2 = 5 * 100.0;  // its sides and its top until the second lands
  ThermalCell upper = cell_at({5, 5, 15}, 1000.0, 120.0, 1);
  upper.open_area_mm2 = 5 * 100.0;
  mesh.cells = {lower, upper};
  mesh.links = {link(0, 1, {0, 0, 100.0}, true)};
  return mesh;
}

struct TwoCubes {
  Material material = test_material();
  Environment env;
  HeatOptions options;
  TwoCubes() {
    material.conductivity_along_W_mK = material.conductivity_across_W_mK =
        material.conductivity_through_W_mK = 1000.0;
    env.bed_insulated = true;
    env.ambient_c = 20.0;
    env.convection_W_m2K = 10.0;
    options.rel_tol = 1e-7;
    options.abs_tol_k = 1e-5;
    options.cooldown_s = 10.0;
    options.birth_interval_s = 1.0;
  }
  HeatResult solve() const {
    HeatOptions o = options;
    const UncertaintyPlan plan = plan_uncertainty(material, env, false);
    o.healing_laws = plan.law_materials();
    HeatResult heat = solve_heat(two_cubes(), 2, 120.0, material, env, o);
    estimate_bands(plan, two_cubes(), 2, 120.0, material, o, heat);
    return heat;
  }
  // The lower cube's temperature as the upper lands, with convection h: T∞ + (T0 − T∞) exp(−h A t / (ρ c V)),
  // A its six faces' 600 mm² (its top open until then).
  double lumped_c(double h) const {
    const double tau = material.density_kg_m3 * material.specific_heat_J_kgK * 1e-6 / (h * 600e-6);
    return env.ambient_c + (material.deposition_temp_c - env.ambient_c) * std::exp(-120.0 / tau);
  }
};

TEST(Uncertainty, ALumpedBodysBandFollowsItsConvectionCoefficient) {
  TwoCubes c;
  c.env.ranges = {uniform("environment.convection", 5.0, 15.0)};
  const HeatResult heat = c.solve();
  ASSERT_EQ(heat.interfaces.size(), 1u);
  const InterfaceResult& r = heat.interfaces[0];
  const double t0 = c.lumped_c(10.0);
  EXPECT_NEAR(r.substrate_c, t0, 0.05);
  // The step is one standard deviation, 10/√12 · ... on the factor: the secant over it, times the sd, gives
  // the band's half-width; the mean of the uniform range is the value, so the band is centred on it.
  const double sd = 10.0 / std::sqrt(12.0);
  const double secant = (c.lumped_c(10.0 + sd) - t0) / sd;
  EXPECT_NEAR(r.substrate_p10_c, t0 - kZ90 * std::abs(secant) * sd, 0.05);
  EXPECT_NEAR(r.substrate_p90_c, t0 + kZ90 * std::abs(secant) * sd, 0.05);
  // Against the derivative dT/dh = −(T − T∞) t A / (ρ c V): the secant's curvature error, a few per cent.
  const double derivative = -(t0 - c.env.ambient_c) * 120.0 * 600e-6 /
                            (c.material.density_kg_m3 * c.material.specific_heat_J_kgK * 1e-6);
  EXPECT_NEAR(secant / derivative, 1.0, 0.1);
  EXPECT_LT(r.substrate_p10_c, r.substrate_c);
  EXPECT_GT(r.substrate_p90_c, r.substrate_c);
}

// The block of test_meshes.hpp with plausible ranges on the heat inputs and the healing law.
struct SampledBlock {
  Material material = block_print().material;
  Environment env = block_print().env;
  HeatOptions options = block_print().options;
  SampledBlock() {
    material.ranges = {
        uniform("conductivity", 0.7, 1.3, true),
        uniform("emissivity", 0.8, 0.95),
        uniform("deposition_temp", 190.0, 210.0),
        uniform("fusion.wlf_c1", 12.0, 20.0),
        {.key = "fusion.reptation_time", .spread = Spread::kLogUniform, .lo = 0.2, .hi = 20.0}};
    material.reptation_time_ref_s = 2.0;
    env.convection_W_m2K = 7.0;
    env.ranges = {uniform("environment.convection", 5.0, 10.0)};
    options.birth_interval_s = 1.0;
  }
};

// Brute force: draws of every input from its range, one solve each; the P10 and P90 of each interface's
// substrate temperature and healing over the draws against the linearised band.
TEST(Uncertainty, TheLinearisedBandAgreesWithSampling) {
  const SampledBlock b;
  const ThermalMesh mesh = block(3, 3, 3);
  const UncertaintyPlan plan = plan_uncertainty(b.material, b.env, false);
  EXPECT_EQ(plan.heat.size(), 4u);  // conductivity, emissivity, deposition, convection
  EXPECT_EQ(plan.laws.size(), 1u);  // C1
  HeatOptions o = b.options;
  o.healing_laws = plan.law_materials();
  HeatResult heat = solve_heat(mesh, 3, 180.0, b.material, b.env, o);
  estimate_bands(plan, mesh, 3, 180.0, b.material, o, heat);

  constexpr int kDraws = 2000;
  std::mt19937 rng(38);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::size_t n = heat.interfaces.size();
  std::vector<std::vector<double>> substrate(n), healing(n);
  HeatOptions plain = b.options;
  for (int d = 0; d < kDraws; ++d) {
    Material m = b.material;
    Environment e = b.env;
    const double k = 0.7 + 0.6 * u(rng);
    m.conductivity_along_W_mK *= k;
    m.conductivity_across_W_mK *= k;
    m.conductivity_through_W_mK *= k;
    m.emissivity = 0.8 + 0.15 * u(rng);
    m.deposition_temp_c = 190.0 + 20.0 * u(rng);
    m.wlf_c1 = 12.0 + 8.0 * u(rng);
    m.reptation_time_ref_s = 0.2 * std::pow(100.0, u(rng));
    e.convection_W_m2K = 5.0 + 5.0 * u(rng);
    const HeatResult r = solve_heat(mesh, 3, 180.0, m, e, plain);
    for (std::size_t i = 0; i < n; ++i) {
      substrate[i].push_back(r.interfaces[i].substrate_c);
      healing[i].push_back(r.interfaces[i].healing);
    }
  }
  const auto quantile = [](std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
  };
  double worst_t = 0.0, worst_h = 0.0, widest_t = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const InterfaceResult& r = heat.interfaces[i];
    worst_t = std::max({worst_t, std::abs(r.substrate_p10_c - quantile(substrate[i], 0.1)),
                        std::abs(r.substrate_p90_c - quantile(substrate[i], 0.9))});
    worst_h = std::max({worst_h, std::abs(r.healing_p10 - quantile(healing[i], 0.1)),
                        std::abs(r.healing_p90 - quantile(healing[i], 0.9))});
    widest_t = std::max(widest_t, r.substrate_p90_c - r.substrate_p10_c);
  }
  // Measured: see docs/physics.md (uncertainty of the verdicts) for the numbers this bounds.
  EXPECT_GT(widest_t, 5.0);
  EXPECT_LT(worst_t, 2.0) << "widest band " << widest_t << " K";
  EXPECT_LT(worst_h, 0.03);
  std::printf("linearised against %d draws: substrate %.2f K, healing %.3f at most (widest band %.1f K)\n",
              kDraws, worst_t, worst_h, widest_t);
}

TEST(Uncertainty, AMarginalInterfaceIsCountedAndDrawnAsMarginal) {
  HeatResult heat;
  InterfaceResult ok, marginal;
  ok.younger = 1;
  ok.area_mm2 = 3.0;
  marginal.younger = 2;
  marginal.area_mm2 = 1.0;
  marginal.verdict = Verdict::kOk;
  marginal.verdict_cold = Verdict::kTooCold;
  marginal.verdict_hot = Verdict::kOk;
  heat.interfaces = {ok, marginal};
  const FusionSummary s = summarise_part(heat);
  EXPECT_EQ(s.marginal, 1u);
  EXPECT_DOUBLE_EQ(s.share(s.marginal_area_mm2), 0.25);
  EXPECT_DOUBLE_EQ(s.share(s.too_cold_p90_area_mm2), 0.25);  // too cold at its cold end
  EXPECT_DOUBLE_EQ(s.share(s.too_cold_p10_area_mm2), 0.0);
  EXPECT_DOUBLE_EQ(s.too_cold_fraction(), 0.0);
  EXPECT_EQ(s.verdict(), Verdict::kOk);
  EXPECT_EQ(s.verdict_at(true), Verdict::kTooCold);
  EXPECT_TRUE(s.marginal_verdict());
  ThermalMesh mesh;
  mesh.cells.resize(3);
  const std::vector<Verdict> cells = cell_verdicts(mesh, heat);
  EXPECT_EQ(cells[1], Verdict::kOk);
  EXPECT_EQ(cells[2], Verdict::kMarginal);
  EXPECT_EQ(to_string(Verdict::kMarginal), "marginal");
}

}  // namespace
}  // namespace beadtwin::thermal
