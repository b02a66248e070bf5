// The shipped LSAM hull mould (scenarios/data/lsam-hull-mould.yaml) end to end, at a test's cost: small
// pictures and the wall cut to its first 110 mm (21 wall layers and one of stock on top, on the 8 of the
// floor), where the two parameter sets already part. Both variants report, and they differ as the scenario
// says: the one-bead set lays one bead as wide as the wall where the two-bead set lays two, with the same
// material per layer, in half the layer time, and lands its wall on a substrate above the support limit.
#include <cstddef>
#include <filesystem>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/toolpath.hpp"
#include "scenarios/input/scenario.hpp"
#include "scenarios/run.hpp"
#include "scenarios/variant_stages.hpp"
#include "tests/read_file.hpp"

namespace beadtwin::scenarios {
namespace {

using testing::read_file;

constexpr double kIn = 25.4;

// What a variant lays in its wall layers (the section "walls", before its stock-on-top layer).
struct WallLayers {
  int layers = 0;
  double length_mm = 0.0;         // depositing moves, all wall layers
  double volume_mm3 = 0.0;        // commanded
  double duration_s = 0.0;        // sum of the layers' times
  double boundary_mm = 0.0;       // of length_mm: boundary passes
  double thin_wall_mm = 0.0;      // of length_mm: thin-wall beads
  double thin_wall_width_mm = 0;  // their widths, length-weighted
};

WallLayers wall_layers(const Variant& v) {
  const Toolpath tp = variant_toolpath(v);
  int walls = -1;
  for (std::size_t s = 0; s < tp.sections.size(); ++s)
    if (tp.sections[s] == "walls") walls = static_cast<int>(s);
  WallLayers w;
  for (const ToolpathLayer& l : tp.layers) {
    if (l.section != walls) continue;
    bool stock_on_top = false;
    for (std::size_t i = l.first_move; i < l.end_move; ++i)
      stock_on_top = stock_on_top || tp.moves[i].feature == Feature::kStockOnTop;
    if (stock_on_top) continue;
    ++w.layers;
    w.duration_s += l.duration_s();
    for (std::size_t i = l.first_move; i < l.end_move; ++i) {
      const Move& m = tp.moves[i];
      if (!m.deposits() || m.kind == MoveKind::kDwell) continue;
      w.length_mm += m.length_mm();
      w.volume_mm3 += m.volume_mm3;
      if (m.feature == Feature::kBoundary) w.boundary_mm += m.length_mm();
      if (m.feature == Feature::kThinWall) {
        w.thin_wall_mm += m.length_mm();
        w.thin_wall_width_mm += m.bead_width_mm * m.length_mm();
      }
    }
  }
  if (w.thin_wall_mm > 0) w.thin_wall_width_mm /= w.thin_wall_mm;
  return w;
}

const SectionRow& section(const VariantResult& v, const std::string& name) {
  for (const SectionRow& s : v.metrics.sections)
    if (s.name == name) return s;
  throw std::runtime_error("no section " + name + " in " + v.name);
}

const GateResult& gate(const VariantResult& v, const std::string& expr) {
  for (const GateResult& g : v.gates)
    if (g.expr == expr) return g;
  throw std::runtime_error("no gate " + expr + " in " + v.name);
}

TEST(LsamMould, ShippedScenarioShowsTheLayerTimeTradeOff) {
  const Scenario sc = load_scenario(
      std::filesystem::path(BEADTWIN_SOURCE_DIR) / "scenarios" / "data" / "lsam-hull-mould.yaml",
      {parse_setting("render.width=160"), parse_setting("render.height=100"),
       parse_setting("sections.walls.z=[40.64, 150]")});
  ASSERT_EQ(sc.variants.size(), 2u);
  ASSERT_EQ(sc.variants[0].name, "two-bead");
  ASSERT_EQ(sc.variants[1].name, "one-bead");

  // The toolpaths: two 0.83 in beads across the 41 mm wall (35 mm and 3 mm of stock on each face) against one
  // bead as wide as the wall, the same material a layer in half the length at the same head speed.
  const WallLayers two = wall_layers(sc.variants[0]);
  const WallLayers one = wall_layers(sc.variants[1]);
  ASSERT_EQ(two.layers, 21);  // 40.64 mm to 150 mm in whole 5.08 mm layers
  ASSERT_EQ(one.layers, two.layers);
  EXPECT_NEAR(two.boundary_mm / two.length_mm, 1.0, 1e-9);
  EXPECT_EQ(one.boundary_mm, 0.0);
  EXPECT_NEAR(one.thin_wall_mm / one.length_mm, 1.0, 1e-9);
  EXPECT_NEAR(one.thin_wall_width_mm, 41.0, 0.5);
  EXPECT_NEAR(one.length_mm / two.length_mm, 0.5, 0.03);
  EXPECT_NEAR(one.volume_mm3 / two.volume_mm3, 1.0, 0.05);
  EXPECT_NEAR(one.duration_s / two.duration_s, 0.5, 0.05);
  EXPECT_NEAR(sc.variants[0].sections.at(1).bead_width_mm, 0.83 * kIn, 1e-9);

  RunOptions o;
  o.out_dir = std::filesystem::temp_directory_path() / "beadtwin_lsam_mould";
  std::filesystem::remove_all(o.out_dir);
  const RunResult r = run_scenario(sc, o);
  ASSERT_EQ(r.variants.size(), 2u);

  // Both variants report, with their pictures, and the comparison sheets put them side by side.
  const auto j = nlohmann::json::parse(read_file(o.out_dir / "report.json"));
  ASSERT_EQ(j["variants"].size(), 2u);
  for (const auto& v : j["variants"]) {
    EXPECT_EQ(v["metrics"]["layers"].get<int>(), 8 + 21 + 1) << v["name"];
    EXPECT_EQ(v["images"].size(), 4u) << v["name"];
    for (const auto& image : v["images"])
      EXPECT_GT(std::filesystem::file_size(o.out_dir / image.get<std::string>()), 1000u) << image;
  }
  EXPECT_EQ(j["sheets"].size(), 4u);
  for (const auto& sheet : j["sheets"])
    EXPECT_TRUE(std::filesystem::exists(o.out_dir / sheet.get<std::string>())) << sheet;
  EXPECT_NE(read_file(o.out_dir / "summary.md").find("| one-bead |"), std::string::npos);

  // The floor prints the same in both; the walls part. Laid in half the time, the one-bead wall lands on a
  // substrate some 30 K hotter than the two-bead wall (168 and 137 C). Both walls carry their beads: judged
  // structurally (the soft height under the bead against the wall's 41 mm, thermal/support.hpp), the
  // one-bead wall's soft layer slumps at most about twice what is allowed and almost nowhere too much, the
  // two-bead wall's less. The hotter landings heal: the one-bead wall is mostly sound and the two-bead
  // wall mostly too cold.
  const VariantResult& a = r.variants[0];
  const VariantResult& b = r.variants[1];
  EXPECT_NEAR(section(a, "floor").substrate_temp_c.mean, section(b, "floor").substrate_temp_c.mean, 3.0);
  const SectionRow& walls_a = section(a, "walls");
  const SectionRow& walls_b = section(b, "walls");
  EXPECT_GT(walls_b.substrate_temp_c.mean, walls_a.substrate_temp_c.mean + 20.0);
  EXPECT_GT(walls_b.slump_ratio_max, walls_a.slump_ratio_max);
  EXPECT_LT(walls_a.too_hot_fraction, 0.01);
  EXPECT_LT(walls_b.too_hot_fraction, 0.05);
  EXPECT_GT(walls_a.too_cold_fraction, 0.5);
  EXPECT_LT(walls_b.too_cold_fraction, 0.1);
  EXPECT_LT(b.metrics.print_time_s, a.metrics.print_time_s);
  EXPECT_NEAR(b.metrics.mass_kg, a.metrics.mass_kg, 0.02 * a.metrics.mass_kg);

  // The gates: neither set is too hot; the two-bead set fails the healing gate, the one-bead set heals
  // better and passes the print-time gate.
  EXPECT_TRUE(gate(a, "interfaces.too_hot_fraction <= 0.3").passed);
  EXPECT_TRUE(gate(b, "interfaces.too_hot_fraction <= 0.3").passed);
  EXPECT_FALSE(gate(a, "interfaces.mean_healing >= 0.85").passed);
  EXPECT_GT(b.metrics.mean_healing, a.metrics.mean_healing + 0.05);
  EXPECT_TRUE(gate(b, "print_time_s <= baseline * 1.2").passed);
}

}  // namespace
}  // namespace beadtwin::scenarios
