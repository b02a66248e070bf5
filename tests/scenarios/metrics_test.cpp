// The metric declarations (scenarios/input/metrics.hpp): each reads its own figure, the names are unique, the
// gate metrics are what gates, "values" and messages know, and a metric not measured is left out.
#include "scenarios/input/metrics.hpp"

#include <cmath>
#include <map>
#include <set>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "scenarios/input/result.hpp"

namespace beadtwin::scenarios {
namespace {

// A run's figures, every one a different number, with a CAD comparison and two sections.
Metrics distinct_metrics() {
  Metrics m;
  m.layers = 12;
  m.print_time_s = 3600.5;
  m.print_length_mm = 51000;
  m.travel_length_mm = 4200;
  m.commanded_volume_mm3 = 9.1e6;
  m.deposited_volume_mm3 = 9.0e6;
  m.mass_kg = 10.8;
  m.material_cost = 86.4;
  m.porosity = 0.021;
  m.min_stock_mm = -1.5;
  m.undercut_fraction = 0.07;
  m.cad.emplace();
  m.cad->max_stock_mm = 6.5;
  m.cad->mean_stock_mm = 2.25;
  m.cad->below_requested_stock_fraction = 0.31;
  m.cad->deviation_rms_mm = 1.75;
  m.cad->machining_waste_fraction = 0.12;
  m.interfaces = 480;
  m.too_hot_fraction = 0.04;
  m.too_cold_fraction = 0.08;
  m.min_healing = 0.61;
  m.mean_healing = 0.97;
  m.still_warm_fraction = 0.015;
  m.max_slump_ratio = 0.35;
  m.fusion.too_cold_fraction_p90 = 0.13;
  m.fusion.too_cold_fraction_p10 = 0.05;
  m.fusion.too_hot_fraction_p90 = 0.06;
  m.fusion.too_hot_fraction_p10 = 0.03;
  m.fusion.marginal_fraction = 0.09;
  m.layer_time_s = {280, 300, 330};
  m.extruder_demand = 0.83;
  m.planned_voids = 2;
  m.planned_void_area_mm2 = 44;
  m.voids = 5;
  m.void_volume_mm3 = 1200;
  m.plough_volume_mm3 = 350;
  m.unsupported_length_mm = 95;
  m.roller_corners = 7;
  m.collisions = 1;
  m.min_layer_fill = 0.93;
  m.max_layer_fill = 1.04;
  m.voxel_size_mm = 2.5;
  m.voxels = 123456;
  m.swept_volume_mm3 = 9.3e6;
  m.redistributed_volume_mm3 = 2.2e5;
  m.thermal_energy_error = 3e-4;
  m.thermal_steps = 4321;
  m.healing_followed_s = 1860;
  SectionRow floor;
  floor.name = "floor";
  floor.layers = 2;
  floor.print_time_s = 610;
  floor.print_length_mm = 9000;
  floor.commanded_volume_mm3 = 1.5e6;
  floor.mass_kg = 1.8;
  floor.material_cost = 14.4;
  floor.mean_layer_time_s = 305;
  floor.interfaces = 40;
  floor.too_hot_fraction = 0.01;
  floor.too_cold_fraction = 0.02;
  floor.healing = 0.71;
  floor.healing_mean = 0.98;
  floor.too_cold_fraction_p90 = 0.035;
  floor.marginal_fraction = 0.025;
  SectionRow walls = floor;
  walls.name = "walls";
  walls.interfaces = 0;  // nothing to heal
  m.sections = {floor, walls};
  return m;
}

// What each declared part-wide metric must read from distinct_metrics(): held against the declarations, so
// a declaration that reads the wrong figure fails here.
const std::map<std::string, double> kExpected = {
    {"layers", 12},
    {"print_time_s", 3600.5},
    {"print_length_mm", 51000},
    {"travel_length_mm", 4200},
    {"commanded_volume_mm3", 9.1e6},
    {"deposited_volume_mm3", 9.0e6},
    {"mass_kg", 10.8},
    {"material_cost", 86.4},
    {"porosity", 0.021},
    {"min_stock_mm", -1.5},
    {"undercut_fraction", 0.07},
    {"max_stock_mm", 6.5},
    {"mean_stock_mm", 2.25},
    {"below_requested_stock_fraction", 0.31},
    {"deviation_rms_mm", 1.75},
    {"machining_waste_fraction", 0.12},
    {"interfaces.count", 480},
    {"interfaces.too_hot_fraction", 0.04},
    {"interfaces.too_cold_fraction", 0.08},
    {"interfaces.min_healing", 0.61},
    {"interfaces.mean_healing", 0.97},
    {"interfaces.still_warm_fraction", 0.015},
    {"interfaces.max_slump_ratio", 0.35},
    {"interfaces.too_cold_fraction_p90", 0.13},
    {"interfaces.too_cold_fraction_p10", 0.05},
    {"interfaces.too_hot_fraction_p90", 0.06},
    {"interfaces.too_hot_fraction_p10", 0.03},
    {"interfaces.marginal_fraction", 0.09},
    {"layer_time_s.min", 280},
    {"layer_time_s.mean", 300},
    {"layer_time_s.max", 330},
    {"extruder_demand", 0.83},
    {"planned_voids", 2},
    {"planned_void_area_mm2", 44},
    {"defects.voids", 5},
    {"defects.void_volume_mm3", 1200},
    {"defects.plough_volume_mm3", 350},
    {"defects.unsupported_length_mm", 95},
    {"defects.roller_corners", 7},
    {"defects.collisions", 1},
    {"layer_fill.min", 0.93},
    {"layer_fill.max", 1.04},
    {"deposit.voxel_size_mm", 2.5},
    {"deposit.voxels", 123456},
    {"deposit.swept_volume_mm3", 9.3e6},
    {"deposit.redistributed_volume_mm3", 2.2e5},
    {"thermal.energy_balance_rel_error", 3e-4},
    {"thermal.cvode_steps", 4321},
    {"thermal.healing_followed_s", 1860},
};

const std::set<std::string> kDiagnostics = {"deposit.voxel_size_mm",
                                            "deposit.voxels",
                                            "deposit.swept_volume_mm3",
                                            "deposit.redistributed_volume_mm3",
                                            "thermal.energy_balance_rel_error",
                                            "thermal.cvode_steps",
                                            "thermal.healing_followed_s"};

TEST(Metrics, EachDeclarationReadsItsOwnFigure) {
  const Metrics m = distinct_metrics();
  std::set<std::string> declared;
  for (const MetricDef& d : metric_defs()) {
    const std::string name(d.name);
    EXPECT_TRUE(declared.insert(name).second) << name << " is declared twice";
    ASSERT_TRUE(kExpected.count(name)) << name << " is declared but not checked here";
    EXPECT_EQ(d.read(m), kExpected.at(name)) << name;
    EXPECT_EQ(m.get(name), kExpected.at(name)) << name;
    EXPECT_EQ(d.gate, !kDiagnostics.count(name)) << name;
    EXPECT_FALSE(d.meaning.empty()) << name;
  }
  EXPECT_EQ(declared.size(), kExpected.size());
  // Counts are whole numbers, and only they are declared as counts.
  EXPECT_EQ(metric_def("interfaces.count").unit, MetricUnit::kCount);
  EXPECT_EQ(metric_def("deposit.voxels").unit, MetricUnit::kCount);
  EXPECT_EQ(metric_def("porosity").unit, MetricUnit::kFraction);
  EXPECT_THROW(metric_def("speediness"), InternalError);
  EXPECT_THROW((void)m.get("speediness"), InternalError);
}

TEST(Metrics, SectionFiguresAreNamedBySection) {
  const Metrics m = distinct_metrics();
  std::set<std::string> declared;
  for (const SectionMetricDef& d : section_metric_defs())
    EXPECT_TRUE(declared.insert(std::string(d.name)).second) << d.name << " is declared twice";
  EXPECT_EQ(m.get("sections.floor.print_time_s"), 610);
  EXPECT_EQ(m.get("sections.floor.interfaces.count"), 40);
  EXPECT_EQ(m.get("sections.floor.interfaces.too_cold_fraction"), 0.02);
  EXPECT_EQ(m.get("sections.floor.interfaces.min_healing"), 0.71);
  EXPECT_EQ(m.get("sections.floor.interfaces.mean_healing"), 0.98);
  EXPECT_EQ(m.get("sections.floor.interfaces.too_cold_fraction_p90"), 0.035);
  EXPECT_EQ(m.get("sections.floor.interfaces.marginal_fraction"), 0.025);
  EXPECT_EQ(m.get("sections.walls.interfaces.min_healing"), std::nullopt);  // no interface
  EXPECT_EQ(m.get("sections.roof.print_time_s"), std::nullopt);             // no such section
  EXPECT_EQ(gate_metric_section("sections.my.walls.mass_kg"), "my.walls");
  EXPECT_EQ(gate_metric_section("mass_kg"), std::nullopt);
}

// "values" (what gates read and a sweep gathers): every gate metric measured, and nothing else.
TEST(Metrics, ValuesAreTheGateMetricsMeasured) {
  Metrics m = distinct_metrics();
  MetricValues v = m.values();
  for (const auto& [name, value] : kExpected)
    EXPECT_EQ(v.count(name), kDiagnostics.count(name) ? 0u : 1u) << name;
  EXPECT_EQ(v.at("sections.walls.layers"), 2);
  EXPECT_FALSE(v.count("sections.walls.interfaces.min_healing"));
  EXPECT_EQ(v.size(), kExpected.size() - kDiagnostics.size() + 2 * section_metric_defs().size() - 2);

  // Without a CAD and without interfaces, what they measure is left out.
  m.min_stock_mm.reset();
  m.undercut_fraction.reset();
  m.cad.reset();
  m.interfaces = 0;
  v = m.values();
  for (const char* name : {"min_stock_mm", "undercut_fraction", "max_stock_mm", "deviation_rms_mm",
                           "interfaces.min_healing", "interfaces.mean_healing"})
    EXPECT_FALSE(v.count(name)) << name;
  EXPECT_TRUE(v.count("interfaces.too_cold_fraction"));
}

TEST(Metrics, GatesKnowTheGateMetricsAndListThemWhenOneIsUnknown) {
  std::vector<std::string> gated;
  for (const MetricDef& d : metric_defs())
    if (d.gate) gated.emplace_back(d.name);
  EXPECT_EQ(gate_metrics(), gated);
  EXPECT_EQ(section_gate_metrics().size(), section_metric_defs().size());
  EXPECT_TRUE(is_gate_metric("interfaces.too_hot_fraction"));
  EXPECT_TRUE(is_gate_metric("sections.walls.mean_layer_time_s"));
  EXPECT_FALSE(is_gate_metric("deposit.voxels"));  // a diagnostic
  EXPECT_FALSE(is_gate_metric("sections.walls.speediness"));
  const std::string message = unknown_metric_message("prosity");
  EXPECT_EQ(message.rfind("unknown metric 'prosity'; expected one of: layers, print_time_s, ", 0), 0u)
      << message;
  EXPECT_NE(message.find("; or sections.NAME. and one of: layers, "), std::string::npos) << message;
  EXPECT_EQ(message.find("deposit.voxels"), std::string::npos) << message;
}

// docs/metrics.md: a row for every declaration, a section's figure under its full name.
TEST(Metrics, MarkdownHasARowForEachMetric) {
  const std::string doc = metrics_markdown();
  for (const MetricDef& d : metric_defs())
    EXPECT_NE(doc.find(fmt::format("| `{}` | ", d.name)), std::string::npos) << d.name;
  for (const SectionMetricDef& d : section_metric_defs())
    EXPECT_NE(doc.find(fmt::format("| `sections.NAME.{}` | ", d.name)), std::string::npos) << d.name;
  EXPECT_NE(doc.find("| `porosity` | fraction | lower | yes |"), std::string::npos);
  EXPECT_NE(doc.find("| `thermal.cvode_steps` | count | – | no |"), std::string::npos);
}

}  // namespace
}  // namespace beadtwin::scenarios
