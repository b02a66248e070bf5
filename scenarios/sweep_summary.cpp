// The sweep's summary.md (scenarios/sweep.hpp): the verdict and the best variants, short enough for a
// pull-request comment.
#include <fmt/format.h>

#include "scenarios/report_text.hpp"
#include "scenarios/sweep.hpp"
#include "scenarios/sweep_report.hpp"

namespace beadtwin::scenarios {
namespace {

// Rows of the summary's table; the whole table is in sweep.html.
constexpr std::size_t kSummaryRows = 20;

}  // namespace

std::string sweep_summary_md(const SweepResult& r) {
  const std::vector<std::size_t> order = report_order(r);
  const std::vector<std::string> keys = set_keys(r);
  const std::vector<std::string> metrics = metric_columns(r);
  std::string s = fmt::format("## beadtwin sweep: {} — {}\n\n{}; sorted by `{}`.\n\n", md(r.scenario_name),
                              r.passed() ? "passed" : "**failed**", counts_text(r), r.sort.text());
  s += "| # | variant |";
  std::string rule = "|---|---|";
  for (const std::string& k : keys) s += fmt::format(" {} |", md(k)), rule += "---|";
  for (const std::string& m : metrics) s += fmt::format(" {} |", md(m)), rule += "---|";
  s += " result |\n" + rule + "---|\n";
  for (std::size_t k = 0; k < order.size() && k < kSummaryRows; ++k) {
    const SweepRecord& rec = r.records[order[k]];
    s += fmt::format("| {} | {} |", k + 1, md(rec.name));
    for (const std::string& key : keys) s += fmt::format(" {} |", md(setting_of(rec, key)));
    for (const std::string& m : metrics) s += fmt::format(" {} |", table_number(rec.value(m)));
    s += fmt::format(" {} |\n", rec.status == SweepStatus::kPassed
                                    ? "pass"
                                    : fmt::format("**{}**", to_string(rec.status)));
  }
  if (order.size() > kSummaryRows)
    s += fmt::format("\n{} more variants in sweep.html.\n", order.size() - kSummaryRows);
  if (r.pareto) {
    std::vector<std::string> names;
    for (const std::size_t i : pareto_front(r.records, r.pareto->first, r.pareto->second))
      names.push_back(r.records[i].name);
    s += fmt::format(
        "\nPareto front of `{}` against `{}`: {}.\n", r.pareto->first.text(), r.pareto->second.text(),
        names.empty() ? std::string("none measured both") : fmt::format("{}", fmt::join(names, ", ")));
  }
  return s;
}

}  // namespace beadtwin::scenarios
