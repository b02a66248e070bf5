// A sweep's records and its reports (scenarios/sweep.hpp).
#include "scenarios/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <numeric>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/atomic_file.hpp"
#include "scenarios/report_text.hpp"
#include "scenarios/run.hpp"

namespace beadtwin::scenarios {
namespace {

using nlohmann::json;

// How much of a failed variant's log its record keeps: the end, where the error is.
constexpr std::size_t kLogTailBytes = 2000;
// Rows of the summary's table (a pull-request comment); the whole table is in sweep.html.
constexpr std::size_t kSummaryRows = 20;

json settings_json(const std::vector<Setting>& settings) {
  json out = json::array();
  for (const Setting& s : settings) out.push_back({{"key", s.key}, {"value", s.value}});
  return out;
}

json gates_json(const std::vector<GateResult>& gates) {
  json out = json::array();
  for (const GateResult& g : gates) {
    json gate = {{"expr", g.expr}, {"passed", g.passed}, {"message", g.message}};
    gate["value"] = g.value ? json(*g.value) : json(nullptr);
    if (g.threshold) gate["threshold"] = *g.threshold;
    out.push_back(gate);
  }
  return out;
}

json record_json(const SweepRecord& r) {
  return {{"name", r.name},
          {"settings", settings_json(r.settings)},
          {"status", to_string(r.status)},
          {"exit_code", r.exit_code},
          {"message", r.message},
          {"values", r.values},
          {"gates", gates_json(r.gates)},
          {"wall_time_s", r.wall_time_s},
          {"worker", r.worker}};
}

std::string log_tail(const std::string& log) {
  if (log.size() <= kLogTailBytes) return log;
  std::string tail = log.substr(log.size() - kLogTailBytes);
  if (const auto nl = tail.find('\n'); nl != std::string::npos && nl + 1 < tail.size()) tail.erase(0, nl + 1);
  return "…\n" + tail;
}

// The record's value of an objective's metric; nullopt when it did not run or did not measure it.
std::optional<double> value_of(const SweepRecord& r, const std::string& metric) {
  const auto it = r.values.find(metric);
  return it == r.values.end() ? std::nullopt : std::optional<double>(it->second);
}

// Whether a is better than b on `o` (strictly).
bool better(double a, double b, const Objective& o) {
  return o.maximise ? a > b : a < b;
}

// The records in the report's order: those that ran by the sort metric, best first (ties and records
// without the metric in the points' order, after the others), then those that failed to run.
std::vector<std::size_t> report_order(const SweepResult& r) {
  std::vector<std::size_t> order(r.records.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const SweepRecord &ra = r.records[a], &rb = r.records[b];
    if (ra.ran() != rb.ran()) return ra.ran();
    const std::optional<double> va = value_of(ra, r.sort.metric), vb = value_of(rb, r.sort.metric);
    if (va.has_value() != vb.has_value()) return va.has_value();
    return va && better(*va, *vb, r.sort);
  });
  return order;
}

// The keys the sweep sets, in the order first set: the table's first columns.
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

// The metrics the table shows: the sort and Pareto metrics, those the gates read, then the headline ones;
// each once, and only those some variant measured.
std::vector<std::string> metric_columns(const SweepResult& r,
                                        const std::vector<std::string>& gate_metric_names) {
  std::vector<std::string> wanted = {r.sort.metric};
  if (r.pareto) wanted.insert(wanted.end(), {r.pareto->first.metric, r.pareto->second.metric});
  wanted.insert(wanted.end(), gate_metric_names.begin(), gate_metric_names.end());
  wanted.insert(wanted.end(),
                {"print_time_s", "mass_kg", "interfaces.too_cold_fraction", "interfaces.too_hot_fraction",
                 "interfaces.min_healing", "porosity", "min_stock_mm"});
  std::vector<std::string> out;
  for (const std::string& m : wanted) {
    if (std::find(out.begin(), out.end(), m) != out.end()) continue;
    if (std::any_of(r.records.begin(), r.records.end(),
                    [&](const SweepRecord& rec) { return value_of(rec, m); }))
      out.push_back(m);
  }
  return out;
}

std::string number(const std::optional<double>& v) {
  return v ? fmt::format("{:.4g}", *v) : std::string("–");
}

// How many records passed, failed a gate, and failed to run.
struct Counts {
  std::size_t passed = 0, gate_failed = 0, failed = 0;
};
Counts counts(const SweepResult& r) {
  Counts c;
  for (const SweepRecord& rec : r.records) {
    if (rec.status == SweepStatus::kPassed) ++c.passed;
    if (rec.status == SweepStatus::kGateFailed) ++c.gate_failed;
    if (rec.status == SweepStatus::kFailed) ++c.failed;
  }
  return c;
}

std::string counts_text(const SweepResult& r) {
  const Counts c = counts(r);
  return fmt::format("{} variant{}: {} passed, {} failed a gate, {} did not run to the end", r.records.size(),
                     r.records.size() == 1 ? "" : "s", c.passed, c.gate_failed, c.failed);
}

// The metrics the gates read, each once (for the table's columns).
std::vector<std::string> gated_metrics(const SweepResult& r) {
  std::vector<std::string> out;
  for (const Gate& g : r.gates)
    if (std::find(out.begin(), out.end(), g.metric) == out.end()) out.push_back(g.metric);
  return out;
}

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
    const std::optional<double> vx = value_of(rec, x.metric), vy = value_of(rec, y.metric);
    if (!rec.ran() || !vx || !vy) continue;
    xs.push_back(*vx), ys.push_back(*vy);
    points.push_back(
        {{"name", rec.name}, {"x", *vx}, {"y", *vy}, {"passed", rec.status == SweepStatus::kPassed}});
  }
  for (const std::size_t i : front)
    line.push_back({{"name", r.records[i].name},
                    {"x", *value_of(r.records[i], x.metric)},
                    {"y", *value_of(r.records[i], y.metric)}});
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

}  // namespace

std::string_view to_string(SweepStatus status) {
  switch (status) {
    case SweepStatus::kPassed:
      return "passed";
    case SweepStatus::kGateFailed:
      return "gate failed";
    case SweepStatus::kFailed:
      return "failed to run";
  }
  return "?";
}

std::string sweep_record_json(const SweepRecord& record) {
  return record_json(record).dump();
}

SweepRecord parse_sweep_record(const std::string& text, const std::string& where) {
  try {
    const json j = json::parse(text);
    SweepRecord r;
    r.name = j.at("name").get<std::string>();
    for (const json& s : j.at("settings"))
      r.settings.push_back({s.at("key").get<std::string>(), s.at("value").get<std::string>()});
    const std::string status = j.at("status").get<std::string>();
    r.status = status == to_string(SweepStatus::kPassed)       ? SweepStatus::kPassed
               : status == to_string(SweepStatus::kGateFailed) ? SweepStatus::kGateFailed
                                                               : SweepStatus::kFailed;
    r.exit_code = j.at("exit_code").get<int>();
    r.message = j.at("message").get<std::string>();
    r.values = j.at("values").get<MetricValues>();
    for (const json& g : j.at("gates")) {
      GateResult gate;
      gate.name = gate.expr = g.at("expr").get<std::string>();
      gate.passed = g.at("passed").get<bool>();
      gate.message = g.at("message").get<std::string>();
      if (!g.at("value").is_null()) gate.value = g.at("value").get<double>();
      if (g.contains("threshold")) gate.threshold = g.at("threshold").get<double>();
      r.gates.push_back(gate);
    }
    r.wall_time_s = j.at("wall_time_s").get<double>();
    r.worker = j.at("worker").get<std::string>();
    return r;
  } catch (const json::exception& e) {
    throw InputError({where, 0, 0}, {}, fmt::format("not a sweep record: {}", e.what()));
  }
}

SweepRecord record_of_run(const SweepPoint& point, const std::filesystem::path& variant_dir, int exit_code,
                          const std::string& log) {
  SweepRecord r;
  r.name = point.name;
  r.settings = point.settings;
  r.exit_code = exit_code;
  if (exit_code != 0 && exit_code != 1) {
    r.status = SweepStatus::kFailed;
    r.message = exit_code < 0 ? "killed by a signal before it finished" : log_tail(log);
    if (exit_code < 0 && !log.empty()) r.message += "\n" + log_tail(log);
    return r;
  }
  const std::filesystem::path report = variant_dir / "report.json";
  try {
    std::ifstream f(report);
    if (!f) throw std::runtime_error("it is missing");
    const json j = json::parse(f);
    r.values = j.at("variants").at(0).at("values").get<MetricValues>();
    r.status = SweepStatus::kPassed;  // until the gates say otherwise
  } catch (const std::exception& e) {
    r.status = SweepStatus::kFailed;
    r.message = fmt::format("its report {} cannot be read: {}", report.string(), e.what());
  }
  return r;
}

void apply_sweep_gates(std::vector<SweepRecord>& records, const std::vector<Gate>& gates) {
  const auto base = std::find_if(records.begin(), records.end(),
                                 [](const SweepRecord& r) { return r.name == "baseline" && r.ran(); });
  const MetricValues* baseline = base == records.end() ? nullptr : &base->values;
  for (SweepRecord& r : records) {
    if (!r.ran()) continue;
    r.gates = evaluate_gates(gates, r.values, baseline);
    r.status = std::all_of(r.gates.begin(), r.gates.end(), [](const GateResult& g) { return g.passed; })
                   ? SweepStatus::kPassed
                   : SweepStatus::kGateFailed;
  }
}

std::vector<std::size_t> pareto_front(const std::vector<SweepRecord>& records, const Objective& x,
                                      const Objective& y) {
  struct P {
    std::size_t i;
    double x, y;
  };
  std::vector<P> ps;
  for (std::size_t i = 0; i < records.size(); ++i) {
    const std::optional<double> vx = value_of(records[i], x.metric), vy = value_of(records[i], y.metric);
    if (records[i].ran() && vx && vy && std::isfinite(*vx) && std::isfinite(*vy)) ps.push_back({i, *vx, *vy});
  }
  std::vector<std::size_t> front;
  for (const P& p : ps) {
    const bool dominated = std::any_of(ps.begin(), ps.end(), [&](const P& q) {
      const bool no_worse = !better(p.x, q.x, x) && !better(p.y, q.y, y);
      return no_worse && (better(q.x, p.x, x) || better(q.y, p.y, y));
    });
    if (!dominated) front.push_back(p.i);
  }
  // Best x first; variants equal on both metrics all stand on the front, in the points' order.
  std::stable_sort(front.begin(), front.end(), [&](std::size_t a, std::size_t b) {
    return better(*value_of(records[a], x.metric), *value_of(records[b], x.metric), x);
  });
  return front;
}

bool SweepResult::passed() const {
  return std::all_of(records.begin(), records.end(),
                     [](const SweepRecord& r) { return r.status == SweepStatus::kPassed; });
}

std::string sweep_json(const SweepResult& r) {
  json axes = json::array();
  for (const SweepAxis& a : r.axes) axes.push_back({{"key", a.key}, {"values", a.values}});
  json records = json::array();
  for (const SweepRecord& rec : r.records) records.push_back(record_json(rec));
  const Counts c = counts(r);
  std::vector<std::string> gate_texts;
  for (const Gate& g : r.gates) gate_texts.push_back(g.expr);
  json out = {{"beadtwin", BEADTWIN_VERSION},
              {"scenario", r.scenario_name},
              {"scenario_file", r.scenario_file},
              {"base_variant", r.base_variant},
              {"axes", axes},
              {"combinations", r.combinations},
              {"gates", gate_texts},
              {"sort", r.sort.text()},
              {"engine", r.engine},
              {"wall_time_s", r.wall_time_s},
              {"resumed", r.resumed},
              {"passed", r.passed()},
              {"counts",
               {{"variants", r.records.size()},
                {"passed", c.passed},
                {"gate_failed", c.gate_failed},
                {"failed", c.failed}}},
              {"variants", records}};
  if (r.pareto) {
    json front = json::array();
    for (const std::size_t i : pareto_front(r.records, r.pareto->first, r.pareto->second))
      front.push_back(r.records[i].name);
    out["pareto"] = {{"x", r.pareto->first.text()}, {"y", r.pareto->second.text()}, {"front", front}};
  }
  return out.dump(2) + "\n";
}

std::string sweep_html(const SweepResult& r) {
  const std::vector<std::size_t> order = report_order(r);
  const std::vector<std::string> keys = set_keys(r);
  const std::vector<std::string> metrics = metric_columns(r, gated_metrics(r));
  const std::vector<std::size_t> front =
      r.pareto ? pareto_front(r.records, r.pareto->first, r.pareto->second) : std::vector<std::size_t>{};
  const std::set<std::size_t> on_front(front.begin(), front.end());

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
  h += "</p>\n";

  if (r.pareto) {
    h += fmt::format("<h2>Pareto front: {} against {}</h2>", esc(r.pareto->first.text()),
                     esc(r.pareto->second.text()));
    h += fmt::format(
        "<p class=legend>{} of the variants that measured both are on the front: no other variant is as good "
        "on both metrics and better on one. Front variants are marked ★ in the table.</p>",
        front.size());
    h += pareto_plot(r, front);
  }

  h += "<h2>Variants</h2><div style=\"overflow-x:auto\"><table class=variants><tr><th>#</th><th "
       "class=l>variant</th>";
  for (const std::string& k : keys) h += fmt::format("<th class=l><code>{}</code></th>", esc(k));
  for (const std::string& m : metrics) h += fmt::format("<th><code>{}</code></th>", esc(m));
  h += "<th class=l>result</th><th>time</th></tr>\n";
  for (std::size_t k = 0; k < order.size(); ++k) {
    const SweepRecord& rec = r.records[order[k]];
    const bool report = rec.ran();
    h += fmt::format(
        "<tr{}><td>{}</td><td class=l>{}{}</td>", rec.status == SweepStatus::kPassed ? "" : " class=hot",
        k + 1,
        report ? fmt::format("<a href=\"variants/{0}/report.html\">{0}</a>", esc(rec.name)) : esc(rec.name),
        on_front.count(order[k]) ? " ★" : "");
    for (const std::string& key : keys) h += fmt::format("<td class=l>{}</td>", esc(setting_of(rec, key)));
    for (const std::string& m : metrics) h += fmt::format("<td>{}</td>", number(value_of(rec, m)));
    // A failed gate by its expression, its message (with the value) on hover.
    std::string result = esc(to_string(rec.status));
    for (const GateResult& g : rec.gates)
      if (!g.passed) result += fmt::format("<br><code title=\"{}\">{}</code>", esc(g.message), esc(g.expr));
    h += fmt::format("<td class=l>{}</td><td>{:.1f} s</td></tr>\n", result, rec.wall_time_s);
  }
  h += "</table></div>\n";

  bool any_failed = false;
  for (const SweepRecord& rec : r.records) {
    if (rec.ran()) continue;
    if (!any_failed) h += "<h2>Variants that did not run to the end</h2>";
    any_failed = true;
    h += fmt::format(
        "<h3>{}</h3><p>{} ({}); its log is <code>variants/{}/log.txt</code>, which ends:</p><pre>{}</pre>",
        esc(rec.name),
        rec.exit_code >= 0 ? fmt::format("exit code {}", rec.exit_code) : std::string("killed"),
        esc(rec.worker.empty() ? std::string("not started") : rec.worker), esc(rec.name), esc(rec.message));
  }
  return h + html_page_end();
}

std::string sweep_summary_md(const SweepResult& r) {
  const std::vector<std::size_t> order = report_order(r);
  const std::vector<std::string> keys = set_keys(r);
  const std::vector<std::string> metrics = metric_columns(r, gated_metrics(r));
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
    for (const std::string& m : metrics) s += fmt::format(" {} |", number(value_of(rec, m)));
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

std::string sweep_junit_xml(const SweepResult& r) {
  std::size_t tests = 0, failures = 0, errors = 0;
  for (const SweepRecord& rec : r.records) {
    if (!rec.ran()) {
      ++tests, ++errors;
      continue;
    }
    for (const GateResult& g : rec.gates) ++tests, failures += g.passed ? 0 : 1;
  }
  std::string x = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  x += fmt::format(
      "<testsuites name=\"beadtwin sweep\" tests=\"{}\" failures=\"{}\" errors=\"{}\" time=\"{:.3f}\">\n",
      tests, failures, errors, r.wall_time_s);
  const std::string suite = esc(r.scenario_name);
  for (const SweepRecord& rec : r.records) {
    const std::string name = esc(rec.name);
    if (!rec.ran()) {
      x += fmt::format(
          "  <testsuite name=\"{0}.{1}\" tests=\"1\" failures=\"0\" errors=\"1\" time=\"{2:.3f}\">\n"
          "    <testcase classname=\"{0}.{1}\" name=\"run\">\n      <error message=\"exit code {3}\" "
          "type=\"run\">{4}</error>\n    </testcase>\n  </testsuite>\n",
          suite, name, rec.wall_time_s, rec.exit_code, esc(rec.message));
      continue;
    }
    x += junit_suite(r.scenario_name, rec.name, rec.gates, rec.wall_time_s);
  }
  x += "</testsuites>\n";
  return x;
}

void write_sweep_reports(const SweepResult& result, const std::filesystem::path& dir) {
  write_file_atomic(dir / "sweep.json", sweep_json(result));
  write_file_atomic(dir / "junit.xml", sweep_junit_xml(result));
  write_file_atomic(dir / "summary.md", sweep_summary_md(result));
  write_file_atomic(dir / "sweep.html", sweep_html(result));
}

}  // namespace beadtwin::scenarios
