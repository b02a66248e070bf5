// The reports as their readers take them, from made-up results: report.json's metrics where their names
// say, summary.md short enough for a pull-request comment, junit.xml valid whatever a gate's message holds.
#include "scenarios/report.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "scenarios/input/metrics.hpp"

#include "tests/read_file.hpp"
#include "tests/scenarios/report_checks.hpp"

namespace beadtwin::scenarios {
namespace {

// `n` variants, the first the baseline at 1 h; variant k prints (1 + k / 10) h, and every third fails
// its gate.
RunResult made_up(int n) {
  RunResult r;
  for (int k = 0; k < n; ++k) {
    VariantResult v;
    v.name = k == 0 ? "baseline" : "set-" + std::to_string(k);
    v.metrics.print_time_s = 3600.0 * (1.0 + k / 10.0);
    v.metrics.mass_kg = 50.0;
    v.metrics.interfaces = 100;
    v.metrics.min_healing = 0.5;
    GateResult g;
    g.expr = "print_time_s <= baseline * 1.5";
    g.passed = k % 3 != 2;
    if (!g.passed) g.message = "print_time_s = " + std::to_string(v.metrics.print_time_s) + ", required ...";
    v.gates.push_back(g);
    v.passed = g.passed;
    r.passed = r.passed && v.passed;
    r.variants.push_back(std::move(v));
  }
  return r;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t at = 0;
  for (std::size_t end; (end = text.find('\n', at)) != std::string::npos; at = end + 1)
    lines.push_back(text.substr(at, end - at));
  return lines;
}

// report.json's "metrics": every declared metric at its dotted path, a count as an integer, null where it
// was not measured; "values" the gate metrics measured; a section's row its figures by their metric names.
TEST(ReportJson, MetricsStandAtTheirDottedNames) {
  using nlohmann::json;
  RunResult r = made_up(1);
  Metrics& m = r.variants[0].metrics;
  m.voxels = 1234;
  m.thermal_steps = 55;
  SectionRow walls;
  walls.name = "walls";
  walls.layers = 3;
  walls.print_time_s = 120;
  m.sections = {walls};
  const json j = json::parse(report_json(r));
  const json& metrics = j["variants"][0]["metrics"];
  for (const MetricDef& d : metric_defs()) {
    std::string pointer = "/" + std::string(d.name);
    std::replace(pointer.begin(), pointer.end(), '.', '/');
    ASSERT_TRUE(metrics.contains(json::json_pointer(pointer))) << d.name;
    const json& v = metrics[json::json_pointer(pointer)];
    const std::optional<double> want = d.read(m);
    if (!want) {
      EXPECT_TRUE(v.is_null()) << d.name << ": " << v;
      continue;
    }
    EXPECT_EQ(v.is_number_integer(), d.unit == MetricUnit::kCount) << d.name << ": " << v;
    EXPECT_EQ(v.get<double>(), *want) << d.name;
  }
  EXPECT_EQ(metrics["interfaces"]["count"].dump(), "100");
  EXPECT_EQ(metrics["print_time_s"].dump(), "3600.0");
  EXPECT_EQ(metrics["deposit"]["voxels"].dump(), "1234");
  EXPECT_TRUE(metrics["min_stock_mm"].is_null());
  EXPECT_TRUE(metrics["cad"].is_null());
  EXPECT_EQ(j["variants"][0]["values"], json(m.values()));
  EXPECT_FALSE(j["variants"][0]["values"].contains("deposit.voxels"));
  const json& row = j["variants"][0]["sections"][0];
  EXPECT_EQ(row["layers"].dump(), "3");
  EXPECT_EQ(row["print_time_s"].dump(), "120.0");
  EXPECT_EQ(row["interfaces"].dump(), "0");  // its interfaces as a layer row has them
  EXPECT_FALSE(row.contains("interfaces.count"));
}

// Against the baseline: the differences, the worse ones in bold, and the failed gates with their messages.
TEST(Summary, MarksDifferencesFromTheBaseline) {
  const RunResult r = made_up(3);
  const std::string s = summary_md(r);
  EXPECT_NE(s.find("**failed** (1 gate)"), std::string::npos) << s;
  const std::vector<std::string> lines = lines_of(s);
  ASSERT_GE(lines.size(), 6u) << s;
  EXPECT_EQ(lines[4].rfind("| baseline (baseline) | pass | 1:00:00 |", 0), 0u) << s;
  // The failed variant comes before the passing one, its longer print marked worse.
  EXPECT_EQ(lines[5].rfind("| set-2 | **fail** | 1:12:00 (**+20.0 %**, worse) |", 0), 0u) << s;
  EXPECT_EQ(lines[6].rfind("| set-1 | pass | 1:06:00 (**+10.0 %**, worse) |", 0), 0u) << s;
  // Equal figures carry no difference.
  EXPECT_EQ(lines[5].find("50.0 ("), std::string::npos) << s;
  EXPECT_NE(s.find("- set-2: print_time_s = 4320"), std::string::npos) << s;
}

// A sweep's summary stays short: twenty variants and twenty failed gates at most, with a count of the rest.
TEST(Summary, StaysShortForManyVariants) {
  const RunResult r = made_up(100);
  const std::string s = summary_md(r);
  const std::vector<std::string> lines = lines_of(s);
  EXPECT_LT(lines.size(), 50u) << s;
  EXPECT_NE(s.find("80 more variants in report.html"), std::string::npos) << s;
  EXPECT_NE(s.find("and 13 more failed gates in report.html"), std::string::npos) << s;  // 33 failed
  // The rows shown: the baseline, then the failed ones.
  const auto rows = std::count_if(lines.begin(), lines.end(),
                                  [](const std::string& l) { return l.rfind("| set-", 0) == 0; });
  EXPECT_EQ(rows, 19);
  EXPECT_EQ(std::count_if(lines.begin(), lines.end(),
                          [](const std::string& l) { return l.find("| **fail** |") != std::string::npos; }),
            19);
}

// A pipe in a variant's name would split its row: it is escaped.
TEST(Summary, EscapesPipesInNames) {
  RunResult r = made_up(2);
  r.variants[1].name = "a|b";
  EXPECT_NE(summary_md(r).find("| a\\|b | pass |"), std::string::npos) << summary_md(r);
}

// Gate messages and names may hold anything a user typed: junit.xml stays valid JUnit XML.
TEST(Junit, StaysValidWhateverTheGatesHold) {
  RunResult r = made_up(4);
  r.variants[2].gates[0].expr = "porosity < 0.1 && \"x\" > 'y'";
  r.variants[2].gates[0].message = "a control \x01 character, a tab\tand <tags> & ampersands";
  const auto path = std::filesystem::temp_directory_path() / "beadtwin_junit_test.xml";
  std::ofstream(path, std::ios::binary) << junit_xml(r);
  const testing::XmlDoc doc = testing::read_junit(path);
  ASSERT_TRUE(doc);
  EXPECT_EQ(testing::xpath_number(doc.get(), "count(//testcase)"), 4);
  EXPECT_EQ(testing::xpath_number(doc.get(), "count(//failure)"), 1);
  EXPECT_EQ(testing::xpath_string(doc.get(), "//testcase[failure]/@name"), "porosity < 0.1 && \"x\" > 'y'");
  EXPECT_EQ(testing::xpath_string(doc.get(), "//failure/@message"),
            "a control ? character, a tab\tand <tags> & ampersands");
}

}  // namespace
}  // namespace beadtwin::scenarios
