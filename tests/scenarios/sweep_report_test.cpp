// What the sweep's reports share (scenarios/sweep_report.hpp): the rows best first with the variants that
// did not run last, and the metric columns the sweep's choices name before the headline ones.
#include "scenarios/sweep_report.hpp"

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "scenarios/input/scenario.hpp"

namespace beadtwin::scenarios {
namespace {

SweepRecord record(const std::string& name, SweepStatus status, const MetricValues& values) {
  SweepRecord r;
  r.name = name;
  r.status = status;
  r.values = values;
  r.settings = {{"sections.walls.speed", name == "a" ? "1 in/s" : "2 in/s"}};
  return r;
}

SweepResult made_up() {
  SweepResult r;
  r.sort = {"porosity", false};
  r.records = {record("a", SweepStatus::kPassed, {{"porosity", 0.03}, {"mass_kg", 5}, {"layers", 4}}),
               record("b", SweepStatus::kFailed, {}),
               record("c", SweepStatus::kGateFailed, {{"porosity", 0.01}, {"mass_kg", 6}, {"layers", 4}}),
               record("d", SweepStatus::kPassed, {{"mass_kg", 4}, {"layers", 4}})};
  return r;
}

TEST(SweepReport, OrdersTheRecordsBestFirstAndThoseThatDidNotRunLast) {
  SweepResult r = made_up();
  EXPECT_EQ(report_order(r), (std::vector<std::size_t>{2, 0, 3, 1}));  // d measured no porosity
  r.sort = {"porosity", true};
  EXPECT_EQ(report_order(r), (std::vector<std::size_t>{0, 2, 3, 1}));
  const SweepCounts c = sweep_counts(r);
  EXPECT_EQ(c.passed, 2u);
  EXPECT_EQ(c.gate_failed, 1u);
  EXPECT_EQ(c.failed, 1u);
  EXPECT_EQ(counts_text(r), "4 variants: 2 passed, 1 failed a gate, 1 did not run to the end");
}

TEST(SweepReport, ShowsTheChosenMetricsFirstThenTheHeadlineOnesThatWereMeasured) {
  SweepResult r = made_up();
  r.gates = {parse_gate_text("layers == 4", {"t", 1, 1}), parse_gate_text("porosity < 0.1", {"t", 2, 1})};
  // porosity (sorted by), layers (gated), then the headline metrics some variant measured: mass_kg.
  EXPECT_EQ(metric_columns(r), (std::vector<std::string>{"porosity", "layers", "mass_kg"}));
  EXPECT_EQ(set_keys(r), (std::vector<std::string>{"sections.walls.speed"}));
  EXPECT_EQ(setting_of(r.records[0], "sections.walls.speed"), "1 in/s");
  EXPECT_EQ(setting_of(r.records[0], "sections.floor.speed"), "");
  EXPECT_EQ(table_number(0.123456), "0.1235");
  EXPECT_EQ(table_number(std::nullopt), "–");
}

}  // namespace
}  // namespace beadtwin::scenarios
