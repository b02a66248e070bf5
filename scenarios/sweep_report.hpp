// What the sweep's reports share (sweep_json.cpp, sweep_html.cpp, sweep_summary.cpp): how the variants
// ended, the order of their rows, and the columns of their tables.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "scenarios/sweep.hpp"

namespace beadtwin::scenarios {

// How many records passed, failed a gate, and failed to run.
struct SweepCounts {
  std::size_t passed = 0, gate_failed = 0, failed = 0;
};
SweepCounts sweep_counts(const SweepResult& r);
// The same in words: "4 variants: 2 passed, 2 failed a gate, 0 did not run to the end".
std::string counts_text(const SweepResult& r);

// The records in the report's order: those that ran by the sort metric, best first (ties and records
// without the metric in the points' order, after the others), then those that failed to run.
std::vector<std::size_t> report_order(const SweepResult& r);

// The keys the sweep sets, in the order first set: the table's first columns.
std::vector<std::string> set_keys(const SweepResult& r);
// The value a record sets `key` to, as written; empty where it does not set it.
std::string setting_of(const SweepRecord& r, const std::string& key);

// The metrics the table shows: the sort and Pareto metrics, those the gates read, then the headline ones;
// each once, and only those some variant measured.
std::vector<std::string> metric_columns(const SweepResult& r);
// A metric's value in a table cell: four significant digits, a dash where it was not measured.
std::string table_number(const std::optional<double>& v);

}  // namespace beadtwin::scenarios
