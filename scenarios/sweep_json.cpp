// A sweep as JSON (scenarios/sweep.hpp): a record's, which worker ranks send and a resumed sweep reads
// back, and sweep.json, the whole sweep for other programs.
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "scenarios/sweep.hpp"
#include "scenarios/sweep_report.hpp"

namespace beadtwin::scenarios {
namespace {

using nlohmann::json;

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

}  // namespace

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

std::string sweep_json(const SweepResult& r) {
  json axes = json::array();
  for (const SweepAxis& a : r.axes) axes.push_back({{"key", a.key}, {"values", a.values}});
  json records = json::array();
  for (const SweepRecord& rec : r.records) records.push_back(record_json(rec));
  const SweepCounts c = sweep_counts(r);
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

}  // namespace beadtwin::scenarios
