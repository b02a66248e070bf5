// A sweep's records: what a variant's run left, the gates over them and their Pareto front
// (scenarios/sweep.hpp). Their JSON is sweep_json.cpp's; the sweep's reports are sweep_report.hpp's.
#include "scenarios/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "scenarios/gate_results.hpp"
#include "scenarios/run.hpp"

namespace beadtwin::scenarios {
namespace {

using nlohmann::json;

// How much of a failed variant's log its record keeps: the end, where the error is.
constexpr std::size_t kLogTailBytes = 2000;

std::string log_tail(const std::string& log) {
  if (log.size() <= kLogTailBytes) return log;
  std::string tail = log.substr(log.size() - kLogTailBytes);
  if (const auto nl = tail.find('\n'); nl != std::string::npos && nl + 1 < tail.size()) tail.erase(0, nl + 1);
  return "…\n" + tail;
}

}  // namespace

std::optional<double> SweepRecord::value(const std::string& metric) const {
  const auto it = values.find(metric);
  return it == values.end() ? std::nullopt : std::optional<double>(it->second);
}

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
    const std::optional<double> vx = records[i].value(x.metric), vy = records[i].value(y.metric);
    if (records[i].ran() && vx && vy && std::isfinite(*vx) && std::isfinite(*vy)) ps.push_back({i, *vx, *vy});
  }
  std::vector<std::size_t> front;
  for (const P& p : ps) {
    const bool dominated = std::any_of(ps.begin(), ps.end(), [&](const P& q) {
      const bool no_worse = !x.better(p.x, q.x) && !y.better(p.y, q.y);
      return no_worse && (x.better(q.x, p.x) || y.better(q.y, p.y));
    });
    if (!dominated) front.push_back(p.i);
  }
  // Best x first; variants equal on both metrics all stand on the front, in the points' order.
  std::stable_sort(front.begin(), front.end(), [&](std::size_t a, std::size_t b) {
    return x.better(*records[a].value(x.metric), *records[b].value(x.metric));
  });
  return front;
}

bool SweepResult::passed() const {
  return std::all_of(records.begin(), records.end(),
                     [](const SweepRecord& r) { return r.status == SweepStatus::kPassed; });
}

}  // namespace beadtwin::scenarios
