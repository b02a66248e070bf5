// Tests of the heat solve's healing integrator (thermal/healing.hpp): which interfaces heal over a step, the
// two-point quadrature of their rate, and the healing of interfaces inside a lumped cell.
#include "thermal/healing.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "tests/thermal/test_meshes.hpp"

namespace beadtwin::thermal {
namespace {

// Three cells in a row along x, each touching the next across an interface (0-1: interface 0, 1-2:
// interface 1). The reference material heals at 1/s at 200 °C (WLF from T_g = 110 °C), not at all below
// 110 °C.
ThermalMesh row() {
  ThermalMesh mesh;
  mesh.voxel_size_mm = 1.0;
  for (int x = 0; x < 3; ++x) mesh.cells.push_back(cell_at({x * 10.0, 0.0, 0.0}, 1000.0, x));
  mesh.links.push_back(link(0, 1, {100.0, 0.0, 0.0}, true));
  mesh.links.push_back(link(1, 2, {100.0, 0.0, 0.0}, true));
  return mesh;
}

TEST(HealingIntegrator, AWarmInterfaceGainsHalfTheStepTimesItsRateAtEachGaussPoint) {
  const Material material;
  const Reptation reptation(material);
  const std::vector<InterfaceResult> interfaces = list_interfaces(row());
  const InterfaceIndex index(interfaces, 3);
  HealingIntegrator healing(material, index);
  // All three born, at 200, 180 and 160 °C at the start of the step, 10 K cooler at its end.
  const std::vector<double> start = {200.0, 180.0, 160.0}, end = {190.0, 170.0, 150.0};
  ASSERT_TRUE(healing.find(index, 3, start, end));
  const std::vector<double> y0 = {196.0, 176.0, 156.0}, y1 = {194.0, 174.0, 154.0};
  healing.integrate(index, 0.5, y0, y1);
  const auto integral = healing.integrals();
  ASSERT_EQ(integral.size(), 2u);
  // Each interface once (though both its cells are warm), at the mean of its two cells' temperatures.
  EXPECT_DOUBLE_EQ(integral[0], 0.5 * reptation.rate_per_s(186.0) + 0.5 * reptation.rate_per_s(184.0));
  EXPECT_DOUBLE_EQ(integral[1], 0.5 * reptation.rate_per_s(166.0) + 0.5 * reptation.rate_per_s(164.0));
  // A second step adds to it.
  ASSERT_TRUE(healing.find(index, 3, end, end));
  healing.integrate(index, 0.5, end, end);
  EXPECT_DOUBLE_EQ(
      healing.integrals()[1],
      0.5 * reptation.rate_per_s(166.0) + 0.5 * reptation.rate_per_s(164.0) + reptation.rate_per_s(160.0));
}

// Isothermal healing (Wool & O'Connor 1981; the isothermal case of Yang & Pitchumani 2002): an interface
// held at one temperature for exactly its reptation time reaches D_h = 1. At 150 °C the reference material's
// WLF law gives t_w = 10^(17.44 · 90/141.6 − 17.44 · 40/91.6) s = 10^3.4690253 s = 2944.593 s, by hand.
TEST(HealingIntegrator, AnInterfaceHeldForItsReptationTimeHealsFully) {
  const Material material;
  const std::vector<InterfaceResult> interfaces = list_interfaces(row());
  const InterfaceIndex index(interfaces, 3);
  HealingIntegrator healing(material, index);
  const double t_w = std::pow(10.0, 3.4690253);
  const std::vector<double> state = {150.0, 150.0, 150.0};
  ASSERT_TRUE(healing.find(index, 3, state, state));
  healing.integrate(index, 0.5 * t_w, state, state);
  EXPECT_NEAR(healing.integrals()[0], 1.0, 1e-6);
  EXPECT_NEAR(healing.integrals()[1], 1.0, 1e-6);
  // A quarter of it: D_h = 0.25^¼ = 0.7071, the fourth-root law.
  HealingIntegrator quarter(material, index);
  ASSERT_TRUE(quarter.find(index, 3, state, state));
  quarter.integrate(index, 0.125 * t_w, state, state);
  EXPECT_NEAR(std::pow(quarter.integrals()[0], 0.25), std::sqrt(0.5), 1e-6);
}

// An interface is warm while the mean of its two cells is at or above the healing threshold.
TEST(HealingIntegrator, AnInterfaceIsWarmWhileItsMeanTemperatureIsAtTheThreshold) {
  const Material material;  // no healing below 110 °C
  const std::vector<InterfaceResult> interfaces = list_interfaces(row());
  const InterfaceIndex index(interfaces, 3);
  const HealingIntegrator healing(material, index);
  const std::vector<double> state = {100.0, 120.0, 99.0};
  EXPECT_TRUE(healing.warm(index, state, 0));   // (100 + 120) / 2 = 110
  EXPECT_FALSE(healing.warm(index, state, 1));  // 109.5
  EXPECT_TRUE(healing.any_warm(index, state));
  const std::vector<double> cold = {100.0, 119.0, 99.0};
  EXPECT_FALSE(healing.any_warm(index, cold));
}

TEST(HealingIntegrator, ColdCellsAndUnbornCellsDoNotHeal) {
  const Material material;  // no healing below 110 °C
  const std::vector<InterfaceResult> interfaces = list_interfaces(row());
  const InterfaceIndex index(interfaces, 3);
  HealingIntegrator healing(material, index);
  const std::vector<double> cold = {100.0, 100.0, 100.0};
  EXPECT_FALSE(healing.find(index, 3, cold, cold));
  // Cell 1 warm at the start of the step, only cells 0 and 1 born: interface 0 heals, interface 1 waits for
  // cell 2.
  const std::vector<double> start = {100.0, 150.0, 230.0}, end = {100.0, 100.0, 230.0};
  ASSERT_TRUE(healing.find(index, 2, start, end));
  const std::vector<double> warm = {150.0, 150.0, 230.0};
  healing.integrate(index, 1.0, warm, warm);
  EXPECT_GT(healing.integrals()[0], 0.0);
  EXPECT_EQ(healing.integrals()[1], 0.0);
  // The threshold with a kelvin's margin: a cell at 109.5 °C at one end of the step may be above 110 between.
  const std::vector<double> just_below = {109.5, 100.0, 100.0};
  EXPECT_TRUE(healing.find(index, 3, just_below, cold));
  const std::vector<double> below = {108.5, 100.0, 100.0};
  EXPECT_FALSE(healing.find(index, 3, below, cold));
}

TEST(HealingIntegrator, AnInterfaceInsideALumpedCellHealsAtItsTemperatureOnceFlushed) {
  const Material material;
  const Reptation reptation(material);
  const std::vector<InterfaceResult> interfaces = list_interfaces(row());
  InterfaceIndex index(interfaces, 3);
  HealingIntegrator healing(material, index);
  // Cells 0 and 1 lumped into model cell 0; cell 2 is model cell 1.
  const std::vector<std::uint32_t> model_of = {0, 0, 1, 2};
  healing.flush_lumps(index);
  index.index(model_of);
  healing.reset_lumps(index);
  const std::vector<double> state = {190.0, 150.0};
  ASSERT_TRUE(healing.find(index, 2, state, state));
  healing.integrate(index, 1.0, state, state);
  EXPECT_EQ(healing.integrals()[0], 0.0);  // held by the lumped cell until flushed
  EXPECT_DOUBLE_EQ(healing.integrals()[1], 2.0 * reptation.rate_per_s(170.0));
  healing.flush_lumps(index);
  EXPECT_DOUBLE_EQ(healing.integrals()[0], 2.0 * reptation.rate_per_s(190.0));
  healing.flush_lumps(index);  // handed over once
  EXPECT_DOUBLE_EQ(healing.integrals()[0], 2.0 * reptation.rate_per_s(190.0));
}

}  // namespace
}  // namespace beadtwin::thermal
