// summary.md (scenarios/report.hpp): the verdict and the variants against the baseline, short enough for a
// pull-request comment.
#include <algorithm>

#include <fmt/format.h>

#include "scenarios/gate_results.hpp"
#include "scenarios/report.hpp"
#include "scenarios/report_columns.hpp"
#include "scenarios/report_text.hpp"
#include "scenarios/run.hpp"

namespace beadtwin::scenarios {

std::string summary_md(const RunResult& result) {
  // Short enough for a pull-request comment: the verdict, the variants against the baseline (the first
  // kSummaryRows, the failed ones first), and the failed gates; the rest is in report.html.
  constexpr std::size_t kSummaryRows = 20;
  int failed_gates = 0;
  for (const auto& v : result.variants)
    for (const auto& g : v.gates) failed_gates += g.passed ? 0 : 1;
  std::string s = fmt::format(
      "## beadtwin: {} — {}\n\n", md(result.scenario ? result.scenario->name : ""),
      result.passed ? "passed"
                    : fmt::format("**failed** ({} gate{})", failed_gates, failed_gates == 1 ? "" : "s"));
  const std::size_t base = result.variants.empty() ? 0 : baseline_index(result.variants);
  const bool compare = result.variants.size() > 1;
  s += "| variant | verdict |";
  std::string rule = "|---|---|";
  for (const VariantColumn& c : variant_columns())
    if (c.in_summary) s += fmt::format(" {} |", c.heading), rule += "---|";
  s += "\n" + rule + "\n";
  std::vector<std::size_t> order(result.variants.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_partition(order.begin(), order.end(), [&](std::size_t i) { return i == base; });
  std::stable_partition(order.begin() + (order.empty() ? 0 : 1), order.end(),
                        [&](std::size_t i) { return !result.variants[i].passed; });
  for (std::size_t k = 0; k < order.size() && k < kSummaryRows; ++k) {
    const std::size_t i = order[k];
    const VariantResult& v = result.variants[i];
    s += fmt::format("| {}{} | {} |", md(v.name), compare && i == base ? " (baseline)" : "",
                     v.passed ? "pass" : "**fail**");
    for (const VariantColumn& c : variant_columns()) {
      if (!c.in_summary) continue;
      const VariantCell cell =
          variant_cell(c, v.metrics, i == base ? nullptr : &result.variants[base].metrics);
      s += " " + cell.text;
      if (!cell.delta.empty())
        s += cell.judgement < 0   ? fmt::format(" (**{}**, worse)", cell.delta)
             : cell.judgement > 0 ? fmt::format(" ({}, better)", cell.delta)
                                  : fmt::format(" ({})", cell.delta);
      s += " |";
    }
    s += "\n";
  }
  if (order.size() > kSummaryRows)
    s += fmt::format("\n{} more variants in report.html.\n", order.size() - kSummaryRows);
  int listed = 0;
  for (const std::size_t i : order)
    for (const auto& g : result.variants[i].gates) {
      if (g.passed) continue;
      if (listed++ == 0) s += "\n";
      if (listed > static_cast<int>(kSummaryRows)) continue;
      s += fmt::format("- {}: {}\n", md(result.variants[i].name), md(g.message));
    }
  if (listed > static_cast<int>(kSummaryRows))
    s += fmt::format("- and {} more failed gates in report.html\n", listed - static_cast<int>(kSummaryRows));
  return s;
}

}  // namespace beadtwin::scenarios
