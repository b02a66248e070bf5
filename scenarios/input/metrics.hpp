// The metrics a run measures, each declared once (scenarios/input/metrics.cpp): its dotted name, its unit,
// which way is better, whether gates may use it, how it is read from the run's figures
// (scenarios/input/result.hpp), and what it means. Everything that names a metric reads this list:
// Metrics::get and Metrics::values, report.json's "metrics" object and "values", the reports' tables, the
// sweep's table, the gate parser's list of known metrics, and `beadtwin metrics` (docs/metrics.md).
//
// A part-wide metric is named as report.json nests it ("interfaces.too_cold_fraction" is
// metrics.interfaces.too_cold_fraction there); a section's figure is named sections.NAME.FIGURE by gates and
// "values", with NAME the section's name.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace beadtwin::scenarios {

struct Metrics;
struct SectionRow;

enum class MetricUnit {
  kCount,  // a whole number, written as an integer in report.json's "metrics"
  kSeconds,
  kMm,
  kMm2,
  kMm3,
  kKg,
  kCurrency,  // the material's price unit (its price_per_kg times kg)
  kFraction,  // a share of a whole, 0 to 1: differences between variants are given in points
  kRatio,     // dimensionless, not a share (degree of healing, demand over a limit)
};
std::string_view to_string(MetricUnit unit);

// Which way a change is an improvement, for marking a variant better or worse than the baseline.
enum class Better { kNeither, kLower, kHigher };
std::string_view to_string(Better better);

// One metric, read from `Row` (Metrics for the part, SectionRow for a section's figures).
template <class Row>
struct MetricDecl {
  std::string_view name;
  MetricUnit unit;
  Better better;
  bool gate;  // gates, sweeps and report.json's "values" may use it; otherwise a diagnostic in "metrics"
  // The value from a run's figures; nullopt where it was not measured (no CAD to compare with, no
  // interface to heal).
  std::optional<double> (*read)(const Row&);
  std::string_view meaning;  // one line, for docs/metrics.md
};
using MetricDef = MetricDecl<Metrics>;
using SectionMetricDef = MetricDecl<SectionRow>;

// The part-wide metrics, gate metrics and diagnostics, in the order messages and docs list them.
std::span<const MetricDef> metric_defs();
// A section's figures, each a gate metric as sections.NAME.FIGURE.
std::span<const SectionMetricDef> section_metric_defs();
// The part-wide metric named `name`. Throws InternalError for a name not declared.
const MetricDef& metric_def(std::string_view name);

// Metric names a gate may use (the part-wide gate metrics).
const std::vector<std::string>& gate_metrics();
// A section's figures a gate may use as sections.NAME.FIGURE (the report's per-section rows).
const std::vector<std::string>& section_gate_metrics();
// Whether a gate may name `name`: one of gate_metrics(), or sections.NAME.FIGURE with a figure of
// section_gate_metrics() (whether the section exists is known once the variants are: check_gate_sections).
bool is_gate_metric(const std::string& name);
// NAME of a sections.NAME.FIGURE metric; nullopt for a part-wide one.
std::optional<std::string> gate_metric_section(const std::string& name);
// The message for a name is_gate_metric() refuses, listing the names it takes.
std::string unknown_metric_message(const std::string& name);

// The metric tables as Markdown (`beadtwin metrics`; docs/metrics.md is this output).
std::string metrics_markdown();

}  // namespace beadtwin::scenarios
