// Tests of the summaries of a heat solution (thermal/summary.hpp), on hand-made results: the per-cell
// summaries the pictures colour the part by (which interfaces count for a cell, and how), the interfaces
// still warm, and the layer-time window of one landing interface against hand-computed waits.
#include "thermal/summary.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace beadtwin::thermal {
namespace {

InterfaceResult interface(std::uint32_t older, std::uint32_t younger, double area_mm2, bool on_top,
                          double substrate_c, double healing, Verdict verdict) {
  InterfaceResult r;
  r.older = older;
  r.younger = younger;
  r.area_mm2 = area_mm2;
  r.on_top = on_top;
  r.substrate_c = substrate_c;
  r.healing = healing;
  r.verdict = verdict;
  return r;
}

// Cell 0 on the table; cell 1 beside it; cell 2 on top of both, more of it on cell 0.
struct Example {
  ThermalMesh mesh;
  HeatResult heat;
  Example() {
    mesh.cells.resize(3);
    heat.interfaces = {interface(0, 1, 50.0, false, 180.0, 0.9, Verdict::kOk),
                       interface(0, 2, 300.0, true, 120.0, 1.0, Verdict::kOk),
                       interface(1, 2, 100.0, true, 160.0, 0.6, Verdict::kTooCold)};
  }
};

TEST(CellSummaries, VerdictIsTheWorstAsTheYoungerCell) {
  const Example e;
  const std::vector<Verdict> v = cell_verdicts(e.mesh, e.heat);
  EXPECT_EQ(v[0], Verdict::kNoInterface);
  EXPECT_EQ(v[1], Verdict::kOk);
  EXPECT_EQ(v[2], Verdict::kTooCold);
}

TEST(CellSummaries, SubstrateIsTheAreaWeightedMeanOfWhatTheCellLandedOn) {
  const Example e;
  const std::vector<double> s = cell_substrate_c(e.mesh, e.heat);
  EXPECT_TRUE(std::isnan(s[0]));  // on the table
  EXPECT_TRUE(std::isnan(s[1]));  // beside an older cell, not on it
  EXPECT_DOUBLE_EQ(s[2], (300.0 * 120.0 + 100.0 * 160.0) / 400.0);
}

TEST(CellSummaries, HealingIsTheLeastAsTheYoungerCell) {
  const Example e;
  const std::vector<double> h = cell_healing(e.mesh, e.heat);
  EXPECT_TRUE(std::isnan(h[0]));
  EXPECT_DOUBLE_EQ(h[1], 0.9);
  EXPECT_DOUBLE_EQ(h[2], 0.6);
}

// One interface, its substrate at 150 °C cooling at 1 K/s towards 18 °C air (τ = 132 s) as the bead landed
// after a 40 s layer, healed to ∫ dt/t_w = 2. Too hot until the substrate has cooled to the 120 °C at which
// what is under it carries the bead (SupportResult::limit_c): 132 ln(132/102) = 34.033 s more. Heals as
// required (0.9) while the contact temperature keeps t_w within 2 / 0.9⁴ of its value at the contact
// temperature it had, (200 + 150)/2 = 175 °C. Under WLF (T_g 110 °C, C1 17.44, C2 51.6 K), by hand: log10
// a(175) = −17.44 · 65/116.6 = −9.7221269, plus log10(2/0.6561) = 0.4840506 makes −9.2380763 = −17.44 x/(51.6
// + x) at x = 58.118526 K, a contact at 168.11853 °C, a substrate at 136.23705 °C, reached 132
// ln(132/118.23705) = 14.534573 s later than 150 °C. Under Arrhenius (150 kJ/mol): 1/T' = 1/448.15 K −
// ln(0.6561/2) R/E_a gives 162.92621 °C, 26.669027 s.
TEST(LayerTimeWindow, WaitsFollowTheCoolingAndTheReptationTimesShift) {
  InterfaceResult r = interface(0, 1, 10.0, true, 150.0, 1.0, Verdict::kOk);
  r.substrate_rate_K_s = -1.0;
  r.healing_integral = 2.0;
  r.support.limit_c = 120.0;
  const std::vector<InterfaceResult> landing = {r};
  Material material;  // deposited at 200 °C, required healing 0.9
  const LayerTimeWindow wlf = layer_time_window(landing, 40.0, material, 18.0, 0.5);
  EXPECT_NEAR(wlf.min_s, 74.033442, 1e-5);
  EXPECT_NEAR(wlf.max_s, 54.534573, 1e-5);
  material.healing_law = HealingLaw::kArrhenius;
  const LayerTimeWindow arrhenius = layer_time_window(landing, 40.0, material, 18.0, 0.5);
  EXPECT_NEAR(arrhenius.min_s, 74.033442, 1e-5);
  EXPECT_NEAR(arrhenius.max_s, 66.669027, 1e-5);
}

// Interfaces still warm when healing ended count in their group's summary, by number and area.
TEST(Summaries, StillWarmInterfacesAreCountedWithTheirArea) {
  Example e;
  e.heat.interfaces[1].still_warm = true;
  const FusionSummary part = summarise_part(e.heat);
  EXPECT_EQ(part.still_warm, 1u);
  EXPECT_DOUBLE_EQ(part.still_warm_area_mm2, 300.0);
  EXPECT_DOUBLE_EQ(part.still_warm_fraction(), 300.0 / 450.0);
}

}  // namespace
}  // namespace beadtwin::thermal
