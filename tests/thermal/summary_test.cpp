// Tests of the per-cell summaries the pictures colour the part by (thermal/summary.hpp), on a hand-made
// result: which interfaces count for a cell, and how.
#include "thermal/summary.hpp"

#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
}  // namespace beadtwin::thermal
