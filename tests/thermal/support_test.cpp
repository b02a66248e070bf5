// Tests of the support of a new bead (thermal/support.hpp): the slump of the soft material under it against
// an independent quadrature, the squeeze-flow limits it joins, the roller's share, and walls of one and of
// six beads side by side, measured on real deposits, judged differently at the same temperatures.
#include "thermal/support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "core/bead.hpp"
#include "core/error.hpp"
#include "tests/sim/lsam_beads.hpp"
#include "thermal/mesh.hpp"

namespace beadtwin::thermal {
namespace {

using testing::kBeadHeight;
using testing::kBeadWidth;

// CF-ABS as scenarios/data/materials/cf-abs-20.yaml has it, for what the support reads.
Material cf_abs() {
  Material m;
  m.density_kg_m3 = 1140.0;
  m.deposition_temp_c = 200.0;
  m.glass_transition_c = 110.0;
  m.softening_temp_c = 110.0;
  m.healing_ref_temp_c = 200.0;
  m.reptation_time_ref_s = 2.0;
  m.viscosity_ref_Pa_s = 1e5;
  m.max_slump = 0.1;
  return m;
}

// η(T) = η_ref · t_w(T) / t_w(T_ref) straight from the healing law, Pa·s.
double viscosity(const Material& m, double temp_c) {
  return m.viscosity_ref_Pa_s * std::exp(Reptation(m).log_time(temp_c));
}

TEST(SupportTest, SlumpOfALinearProfileMatchesAFineQuadrature) {
  const Material m = cf_abs();
  const Support support(m, {});
  // 180 °C at the top of a 20 mm column falling linearly to 100 °C at its bottom: soft down to 110 °C,
  // 17.5 mm. The weight of the soft layer and the 5 mm bead acts for 60 s on a 21 mm wide wall.
  const double top = 20.0, t_top = 180.0, t_bottom = 100.0, width = 21.0, h = 5.0, lt = 60.0;
  const std::vector<double> z{top, 0.0}, t{t_top, t_bottom};
  const SupportResult r = support.judge_column(z, t, width, h, 0.0, lt);
  const double soft = top * (t_top - 110.0) / (t_top - t_bottom);
  EXPECT_NEAR(r.soft_height_mm, soft, 1e-12);
  // ∫ dz / η by the midpoint rule on 200 000 slices.
  double compliance = 0.0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double depth = (i + 0.5) * soft / n;
    compliance += soft / n / viscosity(m, t_top - (t_top - t_bottom) * depth / top);
  }
  const double weight = m.density_kg_m3 * 9.80665 * (soft + h) * 1e-3 * lt;  // Pa·s
  const double expected = weight * compliance / (3.0 + width * width / (4.0 * soft * soft));
  // 1/η tabulated every 0.05 K and taken as exponential between its points: 6e-7.
  EXPECT_NEAR(r.slump_mm / expected, 1.0, 1e-5) << r.slump_mm << " mm against " << expected << " mm";
  EXPECT_DOUBLE_EQ(r.allowed_mm, 0.1 * h);
}

TEST(SupportTest, TheFluidityIntegralHoldsBelowAndAboveItsTable) {
  const Material m = cf_abs();
  const Support support(m, {});
  const auto midpoint = [&](double low, double high) {
    const int n = 200000;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) sum += support.fluidity(low + (i + 0.5) * (high - low) / n);
    return sum * (high - low) / n;
  };
  // Near the softening temperature, where 1/η changes fastest; within one step of the table; and across
  // its top (100 K above the deposition temperature), where Simpson's rule takes over.
  const double soft = support.softening_c(), dep = m.deposition_temp_c;
  for (const auto& [low, high] : {std::pair{soft - 5.0, soft + 3.0}, std::pair{soft + 1.01, soft + 1.03},
                                  std::pair{dep + 60.0, dep + 160.0}}) {
    const double expected = midpoint(std::max(low, soft), high);
    EXPECT_NEAR(support.fluidity_integral(low, high) / expected, 1.0, 1e-5) << low << " to " << high << " °C";
  }
  EXPECT_EQ(support.fluidity_integral(soft - 20.0, soft - 1.0), 0.0);
}

TEST(SupportTest, AWideThinLayerSqueezesOutAndATallNarrowOneFlowsAsAColumn) {
  const Material m = cf_abs();
  const Support support(m, {});
  const double temp = 150.0, h = 5.0, lt = 30.0;
  const double eta = viscosity(m, temp);
  const auto slump = [&](double soft, double width) {
    const std::vector<double> z{soft, 0.0}, t{temp, temp};
    return support.judge_column(z, t, width, h, 0.0, lt).slump_mm;
  };
  const auto pressure = [&](double soft) { return m.density_kg_m3 * 9.80665 * (soft + h) * 1e-3; };
  // Squeeze flow against the rigid wall below, shear-free on top: strain rate 4 p H² / (η W²).
  const double thin = 2.0, wide = 2000.0;
  const double squeeze = pressure(thin) * lt * 4.0 * thin * thin / (eta * wide * wide) * thin;
  EXPECT_NEAR(slump(thin, wide) / squeeze, 1.0, 1e-4);
  // A free column in uniaxial compression (Trouton): p / (3 η).
  const double tall = 500.0, narrow = 1.0;
  const double column = pressure(tall) * lt / (3.0 * eta) * tall;
  EXPECT_NEAR(slump(tall, narrow) / column, 1.0, 1e-5);
}

TEST(SupportTest, TheRollerAddsItsPressureOverItsContactTime) {
  const Material m = cf_abs();
  const SupportLoad roller{.roller_pressure_Pa = 3e5, .roller_contact_mm = 12.7};
  const Support without(m, {}), with(m, roller);
  const std::vector<double> z{15.0, 5.0, 0.0}, t{160.0, 140.0, 105.0};
  const double width = 21.0, h = 5.0, speed = 100.0, lt = 40.0;
  const SupportResult a = without.judge_column(z, t, width, h, speed, lt);
  const SupportResult b = with.judge_column(z, t, width, h, speed, lt);
  // Once for every layer laid on the soft material (14.3 mm of it: 2.86 layers).
  const double weight = m.density_kg_m3 * 9.80665 * (a.soft_height_mm + h) * 1e-3 * lt;
  const double pressed = 3e5 * 12.7 / speed * a.soft_height_mm / h;
  EXPECT_NEAR(a.soft_height_mm, 10.0 + 5.0 * 30.0 / 35.0, 1e-12);
  EXPECT_NEAR(b.slump_mm / a.slump_mm, (weight + pressed) / weight, 1e-9);
  // A harder load is carried only by a cooler substrate.
  EXPECT_LT(b.limit_c, a.limit_c);
  // Nothing soft under the bead: nothing slumps.
  const std::vector<double> cold{100.0, 100.0, 100.0};
  EXPECT_EQ(with.judge_column(z, cold, width, h, speed, lt).slump_mm, 0.0);
}

TEST(SupportTest, BadMaterialValuesAreInputErrorsNamingTheKey) {
  Material m = cf_abs();
  m.viscosity_ref_Pa_s = 0.0;
  try {
    Support(m, {});
    FAIL() << "a zero viscosity was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "fusion.viscosity");
  }
  m = cf_abs();
  m.max_slump = -0.1;
  EXPECT_THROW(Support(m, {}), InputError);
}

// `count` LSAM beads side by side, `layers` high, 300 mm long.
Toolpath wall(int count, int layers) {
  return testing::bead_block(count, layers, 300.0);
}

struct Landing {
  std::uint32_t older = 0, younger = 0;
};

// A landing of the top layer on the one under it, in the middle of the wall's length and width.
Landing middle_landing(const ThermalMesh& mesh, int top_layer, double y_mm) {
  Landing best;
  double best_distance = 1e300;
  for (const ThermalLink& l : mesh.links) {
    if (!l.interface || mesh.cells[l.b].layer != top_layer || mesh.cells[l.a].layer != top_layer - 1)
      continue;
    if (l.area_vector_mm2.z() < 0.5 * l.area_mm2()) continue;
    const Eigen::Vector3d c = mesh.cells[l.b].centroid_mm;
    const double d = std::abs(c.x() - 150.0) + std::abs(c.y() - y_mm);
    if (d < best_distance) best = {l.a, l.b}, best_distance = d;
  }
  return best;
}

TEST(SupportTest, OneBeadAndSixBeadWallsAtTheSameTemperaturesGetDifferentVerdicts) {
  const Material m = cf_abs();
  const SupportLoad roller{.roller_pressure_Pa = 3e5, .roller_contact_mm = 12.7};
  const Support support(m, roller);
  constexpr int kLayers = 6;
  const double pitch = bead_area_mm2(kBeadWidth, kBeadHeight) / kBeadHeight;
  sim::DepositOptions options;
  options.voxel_size_mm = kBeadHeight / 5.0;
  const Toolpath one = wall(1, kLayers), six = wall(6, kLayers);
  const ThermalMesh one_mesh = build_thermal_mesh(one, sim::deposit(one, options));
  const ThermalMesh six_mesh = build_thermal_mesh(six, sim::deposit(six, options));
  const Landing a = middle_landing(one_mesh, kLayers - 1, 0.0);
  const Landing b = middle_landing(six_mesh, kLayers - 1, 2.5 * pitch);
  ASSERT_NE(a.younger, 0u);
  ASSERT_NE(b.younger, 0u);
  // The walls' widths as the mesh measured them: one bead's, and six beads at their pitch.
  EXPECT_NEAR(one_mesh.support[a.older].wall_width_mm, kBeadWidth, 2.0 * options.voxel_size_mm);
  EXPECT_NEAR(six_mesh.support[b.older].wall_width_mm, 5.0 * pitch + kBeadWidth, 2.0 * options.voxel_size_mm);
  // Both walls soft to the table at one temperature and carrying their weight for the same time, 30 min
  // (longer than either took to print: min_load_s decides), so that only their shapes differ.
  const auto judge = [&](const ThermalMesh& mesh, const Landing& l, double temp_c) {
    return support.judge(mesh.support, l.older, l.younger, 1800.0,
                         [temp_c](std::uint32_t) { return temp_c; });
  };
  ASSERT_LT(six.total_time_s(), 1800.0);
  const double limit_one = judge(one_mesh, a, 150.0).limit_c, limit_six = judge(six_mesh, b, 150.0).limit_c;
  EXPECT_GT(limit_six, limit_one + 3.0) << "the wider wall carries a hotter soft layer";
  const double between = 0.5 * (limit_one + limit_six);
  const SupportResult on_one = judge(one_mesh, a, between), on_six = judge(six_mesh, b, between);
  EXPECT_TRUE(on_one.too_hot()) << on_one.slump_mm << " mm slump, " << on_one.allowed_mm << " allowed";
  EXPECT_FALSE(on_six.too_hot()) << on_six.slump_mm << " mm slump, " << on_six.allowed_mm << " allowed";
  EXPECT_NEAR(on_one.soft_height_mm, on_six.soft_height_mm, 2.0 * options.voxel_size_mm);
  // At its own limit each slumps by what is allowed (within the search's tolerance, half a per cent).
  const SupportResult at_limit = judge(one_mesh, a, limit_one);
  EXPECT_NEAR(at_limit.slump_mm / at_limit.allowed_mm, 1.0, 0.01);
}

TEST(SupportTest, ABeadCutIntoSlicesThroughItsHeightIsJudgedAsOneCellThrough) {
  // The one-bead wall meshed with one and with five cells through each bead: the column under a landing
  // walks down through the slices (each rests on the one under it, born with it), the wall is soft to the
  // table either way, and the hot edge is the same within the meshes' difference in heights.
  const Material m = cf_abs();
  const Support support(m, {.roller_pressure_Pa = 3e5, .roller_contact_mm = 12.7});
  constexpr int kLayers = 6;
  sim::DepositOptions options;
  options.voxel_size_mm = kBeadHeight / 5.0;
  const Toolpath one = wall(1, kLayers);
  const sim::Deposit deposit = sim::deposit(one, options);
  const ThermalMesh whole = build_thermal_mesh(one, deposit);
  const ThermalMesh sliced = build_thermal_mesh(one, deposit, {.cells_through = 5});
  const Landing a = middle_landing(whole, kLayers - 1, 0.0), b = middle_landing(sliced, kLayers - 1, 0.0);
  ASSERT_NE(a.younger, 0u);
  ASSERT_NE(b.younger, 0u);
  // The sliced landing's older cell is the top slice of the bead under it: its column holds five cells.
  const std::uint32_t top = sliced.support[b.older].bead_top;
  int slices = 0;
  for (std::uint32_t c = top; c != SupportCell::kNone && sliced.support[c].bead_top == top;
       c = sliced.support[c].below)
    ++slices;
  EXPECT_EQ(slices, 5);
  const auto judge = [&](const ThermalMesh& mesh, const Landing& l) {
    return support.judge(mesh.support, l.older, l.younger, 1800.0, [](std::uint32_t) { return 150.0; });
  };
  const SupportResult on_whole = judge(whole, a), on_sliced = judge(sliced, b);
  EXPECT_NEAR(on_sliced.soft_height_mm, on_whole.soft_height_mm, 0.5 * kBeadHeight);
  EXPECT_NEAR(on_sliced.soft_height_mm, (kLayers - 1) * kBeadHeight, 0.5 * kBeadHeight);
  EXPECT_NEAR(on_sliced.slump_mm / on_whole.slump_mm, 1.0, 0.15);
  EXPECT_NEAR(on_sliced.limit_c, on_whole.limit_c, 1.0);
}

}  // namespace
}  // namespace beadtwin::thermal
