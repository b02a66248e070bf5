// sweep.html (scenarios/sweep.hpp): the sweep for people, with its Pareto plot and every variant's row.
#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "scenarios/report_text.hpp"
#include "scenarios/sweep.hpp"
#include "scenarios/sweep_report.hpp"

namespace beadtwin::scenarios {
namespace {

using nlohmann::json;

// Significant digits for a plot's tooltip: enough for the spread of the values.
int digits_for(const std::vector<double>& values) {
  if (values.empty()) return 3;
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  const double span = std::max(std::abs(*hi - *lo), 1e-12 * std::max(std::abs(*hi), 1.0));
  return std::clamp(static_cast<int>(std::ceil(-std::log10(span))) + 2, 0, 8);
}

std::string pareto_plot(const SweepResult& r, const std::vector<std::size_t>& front) {
  const auto& [x, y] = *r.pareto;
  json points = json::array(), line = json::array();
  std::vector<double> xs, ys;
  for (std::size_t i = 0; i < r.records.size(); ++i) {
    const SweepRecord& rec = r.records[i];
    const std::optional<double> vx = rec.value(x.metric), vy = rec.value(y.metric);
    if (!rec.ran() || !vx || !vy) continue;
    xs.push_back(*vx), ys.push_back(*vy);
    points.push_back(
        {{"name", rec.name}, {"x", *vx}, {"y", *vy}, {"passed", rec.status == SweepStatus::kPassed}});
  }
  for (const std::size_t i : front)
    line.push_back({{"name", r.records[i].name},
                    {"x", *r.records[i].value(x.metric)},
                    {"y", *r.records[i].value(y.metric)}});
  const auto label = [](const Objective& o) {
    return fmt::format("{} ({} is better)", o.metric, o.maximise ? "higher" : "lower");
  };
  return plot_html(
      {{"kind", "pareto"},
       {"label", fmt::format("the variants by {} and {}, with their Pareto front", x.metric, y.metric)},
       {"x_label", label(x)},
       {"y_label", label(y)},
       {"x_digits", digits_for(xs)},
       {"y_digits", digits_for(ys)},
       {"points", points},
       {"front", line}},
      "the table below and in sweep.json");
}

// The verdict and what was swept: the scenario, the axes, the sort and the gates.
std::string sweep_head_html(const SweepResult& r) {
  std::string h = html_page_start("beadtwin sweep — " + r.scenario_name);
  h += fmt::format("<h1>Sweep of {}</h1>", esc(r.scenario_name));
  h += fmt::format("<p><span class=\"verdict {}\">{}</span> beadtwin {} · {} · {} · {:.1f} s{}</p>",
                   r.passed() ? "pass" : "fail", r.passed() ? "PASSED" : "FAILED", BEADTWIN_VERSION,
                   esc(counts_text(r)), esc(r.engine), r.wall_time_s,
                   r.resumed ? fmt::format(" · {} taken from an earlier run of this sweep", r.resumed) : "");
  h += fmt::format("<p class=muted>Scenario {}, variant <code>{}</code>, with", esc(r.scenario_file),
                   esc(r.base_variant));
  for (const SweepAxis& a : r.axes)
    h +=
        fmt::format(" <code>{}</code> = {};", esc(a.key), esc(fmt::format("{}", fmt::join(a.values, " | "))));
  if (r.combinations > 0) h += fmt::format(" {} combinations from a file;", r.combinations);
  h += fmt::format(" sorted by <code>{}</code>.", esc(r.sort.text()));
  for (std::size_t i = 0; i < r.gates.size(); ++i)
    h += fmt::format("{}<code>{}</code>{}", i == 0 ? " Gates: " : "; ", esc(r.gates[i].expr),
                     i + 1 == r.gates.size() ? "." : "");
  return h + "</p>\n";
}

std::string pareto_html(const SweepResult& r, const std::vector<std::size_t>& front) {
  std::string h = fmt::format("<h2>Pareto front: {} against {}</h2>", esc(r.pareto->first.text()),
                              esc(r.pareto->second.text()));
  h += fmt::format(
      "<p class=legend>{} of the variants that measured both are on the front: no other variant is as good "
      "on both metrics and better on one. Front variants are marked ★ in the table.</p>",
      front.size());
  return h + pareto_plot(r, front);
}

// A failed gate by its expression, its message (with the value) on hover.
std::string result_html(const SweepRecord& rec) {
  std::string result = esc(to_string(rec.status));
  for (const GateResult& g : rec.gates)
    if (!g.passed) result += fmt::format("<br><code title=\"{}\">{}</code>", esc(g.message), esc(g.expr));
  return result;
}

// Every variant in the report's order: what it set, what it measured, how it ended; ★ on the front.
std::string variants_html(const SweepResult& r, const std::vector<std::size_t>& front) {
  const std::vector<std::size_t> order = report_order(r);
  const std::vector<std::string> keys = set_keys(r);
  const std::vector<std::string> metrics = metric_columns(r);
  const std::set<std::size_t> on_front(front.begin(), front.end());
  std::string h =
      "<h2>Variants</h2><div style=\"overflow-x:auto\"><table class=variants><tr><th>#</th><th "
      "class=l>variant</th>";
  for (const std::string& k : keys) h += fmt::format("<th class=l><code>{}</code></th>", esc(k));
  for (const std::string& m : metrics) h += fmt::format("<th><code>{}</code></th>", esc(m));
  h += "<th class=l>result</th><th>time</th></tr>\n";
  for (std::size_t k = 0; k < order.size(); ++k) {
    const SweepRecord& rec = r.records[order[k]];
    h += fmt::format("<tr{}><td>{}</td><td class=l>{}{}</td>",
                     rec.status == SweepStatus::kPassed ? "" : " class=hot", k + 1,
                     rec.ran() ? fmt::format("<a href=\"variants/{0}/report.html\">{0}</a>", esc(rec.name))
                               : esc(rec.name),
                     on_front.count(order[k]) ? " ★" : "");
    for (const std::string& key : keys) h += fmt::format("<td class=l>{}</td>", esc(setting_of(rec, key)));
    for (const std::string& m : metrics) h += fmt::format("<td>{}</td>", table_number(rec.value(m)));
    h += fmt::format("<td class=l>{}</td><td>{:.1f} s</td></tr>\n", result_html(rec), rec.wall_time_s);
  }
  return h + "</table></div>\n";
}

// The variants that did not run to the end, each with the end of its log.
std::string failed_html(const SweepResult& r) {
  std::string h;
  for (const SweepRecord& rec : r.records) {
    if (rec.ran()) continue;
    if (h.empty()) h += "<h2>Variants that did not run to the end</h2>";
    h += fmt::format(
        "<h3>{}</h3><p>{} ({}); its log is <code>variants/{}/log.txt</code>, which ends:</p><pre>{}</pre>",
        esc(rec.name),
        rec.exit_code >= 0 ? fmt::format("exit code {}", rec.exit_code) : std::string("killed"),
        esc(rec.worker.empty() ? std::string("not started") : rec.worker), esc(rec.name), esc(rec.message));
  }
  return h;
}

}  // namespace

std::string sweep_html(const SweepResult& r) {
  const std::vector<std::size_t> front =
      r.pareto ? pareto_front(r.records, r.pareto->first, r.pareto->second) : std::vector<std::size_t>{};
  std::string h = sweep_head_html(r);
  if (r.pareto) h += pareto_html(r, front);
  h += variants_html(r, front);
  h += failed_html(r);
  return h + html_page_end();
}

}  // namespace beadtwin::scenarios
