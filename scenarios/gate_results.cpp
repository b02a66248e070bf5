#include "scenarios/gate_results.hpp"

#include <algorithm>
#include <optional>
#include <string>
#include <string_view>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "scenarios/input/metrics.hpp"

namespace beadtwin::scenarios {
namespace {

bool compare(double value, GateOp op, double threshold) {
  switch (op) {
    case GateOp::kLess:
      return value < threshold;
    case GateOp::kLessEqual:
      return value <= threshold;
    case GateOp::kGreater:
      return value > threshold;
    case GateOp::kGreaterEqual:
      return value >= threshold;
    case GateOp::kEqual:
      return value == threshold;
    case GateOp::kNotEqual:
      return value != threshold;
  }
  return false;
}

std::optional<double> lookup(const MetricValues& values, const std::string& name) {
  const auto it = values.find(name);
  return it == values.end() ? std::nullopt : std::optional<double>(it->second);
}

// The sections a run measured, from their sections.NAME.layers values (every section has its layer count).
std::vector<std::string> section_names(const MetricValues& values) {
  constexpr std::string_view kPrefix = "sections.", kSuffix = ".layers";
  std::vector<std::string> names;
  for (const auto& [name, value] : values)
    if (name.starts_with(kPrefix) && name.ends_with(kSuffix) && name.size() > kPrefix.size() + kSuffix.size())
      names.push_back(name.substr(kPrefix.size(), name.size() - kPrefix.size() - kSuffix.size()));
  return names;
}

}  // namespace

std::vector<GateResult> evaluate_gates(const std::vector<Gate>& gates, const MetricValues& values,
                                       const MetricValues* baseline) {
  std::vector<GateResult> out;
  for (const Gate& g : gates) {
    GateResult r;
    r.name = g.expr;
    r.expr = g.expr;
    r.value = lookup(values, g.metric);
    std::optional<double> threshold = g.threshold;
    const std::optional<double> base = baseline ? lookup(*baseline, g.metric) : std::nullopt;
    if (g.relative) {
      threshold = base ? std::optional<double>(*base * g.factor + g.offset) : std::nullopt;
      r.threshold = threshold;
    }
    if (!r.value) {
      r.passed = false;
      r.message = fmt::format("{} is not measured for this run", g.metric);
      if (const std::optional<std::string> section = gate_metric_section(g.metric)) {
        const std::vector<std::string> names = section_names(values);
        if (std::find(names.begin(), names.end(), *section) == names.end())
          r.message =
              fmt::format("{}: this run has no section '{}'; its sections are: {}", g.metric, *section,
                          names.empty() ? std::string("none") : fmt::format("{}", fmt::join(names, ", ")));
      }
    } else if (!threshold) {
      r.passed = false;
      r.message = baseline ? fmt::format("{} is not measured for the baseline", g.metric)
                           : std::string("there is no baseline variant to compare with");
    } else {
      r.passed = compare(*r.value, g.op, *threshold);
      if (!r.passed)
        r.message = g.relative ? fmt::format("{} = {:.6g}, required {} (baseline's: {:.6g}, so {:.6g})",
                                             g.metric, *r.value, g.expr, *base, *threshold)
                               : fmt::format("{} = {:.6g}, required {}", g.metric, *r.value, g.expr);
    }
    out.push_back(r);
  }
  return out;
}

std::vector<GateResult> evaluate_gates(const std::vector<Gate>& gates, const Metrics& metrics,
                                       const Metrics* baseline) {
  const MetricValues base = baseline ? baseline->values() : MetricValues{};
  return evaluate_gates(gates, metrics.values(), baseline ? &base : nullptr);
}

std::size_t baseline_index(const std::vector<VariantResult>& variants) {
  for (std::size_t i = 0; i < variants.size(); ++i)
    if (variants[i].name == "baseline") return i;
  return 0;
}

}  // namespace beadtwin::scenarios
