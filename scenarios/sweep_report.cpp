// What the sweep's reports share, and writing them (scenarios/sweep_report.hpp, scenarios/sweep.hpp).
#include "scenarios/sweep_report.hpp"

#include <algorithm>
#include <numeric>
#include <string_view>

#include <fmt/format.h>

#include "core/atomic_file.hpp"
#include "scenarios/input/metrics.hpp"

namespace beadtwin::scenarios {
namespace {

// The metrics every sweep's table shows, after those the sweep sorts, plots and gates by.
constexpr std::string_view kHeadlineMetrics[] = {"print_time_s",
                                                 "mass_kg",
                                                 "interfaces.too_cold_fraction",
                                                 "interfaces.too_hot_fraction",
                                                 "interfaces.min_healing",
                                                 "porosity",
                                                 "min_stock_mm"};

// The metrics the gates read, each once.
std::vector<std::string> gated_metrics(const SweepResult& r) {
  std::vector<std::string> out;
  for (const Gate& g : r.gates)
    if (std::find(out.begin(), out.end(), g.metric) == out.end()) out.push_back(g.metric);
  return out;
}

}  // namespace

SweepCounts sweep_counts(const SweepResult& r) {
  SweepCounts c;
  for (const SweepRecord& rec : r.records) {
    if (rec.status == SweepStatus::kPassed) ++c.passed;
    if (rec.status == SweepStatus::kGateFailed) ++c.gate_failed;
    if (rec.status == SweepStatus::kFailed) ++c.failed;
  }
  return c;
}

std::string counts_text(const SweepResult& r) {
  const SweepCounts c = sweep_counts(r);
  return fmt::format("{} variant{}: {} passed, {} failed a gate, {} did not run to the end", r.records.size(),
                     r.records.size() == 1 ? "" : "s", c.passed, c.gate_failed, c.failed);
}

std::vector<std::size_t> report_order(const SweepResult& r) {
  std::vector<std::size_t> order(r.records.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const SweepRecord &ra = r.records[a], &rb = r.records[b];
    if (ra.ran() != rb.ran()) return ra.ran();
    const std::optional<double> va = ra.value(r.sort.metric), vb = rb.value(r.sort.metric);
    if (va.has_value() != vb.has_value()) return va.has_value();
    return va && r.sort.better(*va, *vb);
  });
  return order;
}

std::vector<std::string> set_keys(const SweepResult& r) {
  std::vector<std::string> keys;
  for (const SweepRecord& rec : r.records)
    for (const Setting& s : rec.settings)
      if (std::find(keys.begin(), keys.end(), s.key) == keys.end()) keys.push_back(s.key);
  return keys;
}

std::string setting_of(const SweepRecord& r, const std::string& key) {
  for (const Setting& s : r.settings)
    if (s.key == key) return s.value;
  return {};
}

std::vector<std::string> metric_columns(const SweepResult& r) {
  std::vector<std::string> wanted = {r.sort.metric};
  if (r.pareto) wanted.insert(wanted.end(), {r.pareto->first.metric, r.pareto->second.metric});
  const std::vector<std::string> gated = gated_metrics(r);
  wanted.insert(wanted.end(), gated.begin(), gated.end());
  for (const std::string_view m : kHeadlineMetrics) wanted.emplace_back(metric_def(m).name);
  std::vector<std::string> out;
  for (const std::string& m : wanted) {
    if (std::find(out.begin(), out.end(), m) != out.end()) continue;
    if (std::any_of(r.records.begin(), r.records.end(), [&](const SweepRecord& rec) { return rec.value(m); }))
      out.push_back(m);
  }
  return out;
}

std::string table_number(const std::optional<double>& v) {
  return v ? fmt::format("{:.4g}", *v) : std::string("–");
}

void write_sweep_reports(const SweepResult& result, const std::filesystem::path& dir) {
  write_file_atomic(dir / "sweep.json", sweep_json(result));
  write_file_atomic(dir / "junit.xml", sweep_junit_xml(result));
  write_file_atomic(dir / "summary.md", sweep_summary_md(result));
  write_file_atomic(dir / "sweep.html", sweep_html(result));
}

}  // namespace beadtwin::scenarios
