// The variants table's columns (scenarios/report_columns.hpp).
#include "scenarios/report_columns.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "scenarios/input/metrics.hpp"
#include "scenarios/report_text.hpp"

namespace beadtwin::scenarios {
namespace {

std::string percent(double v) {
  return fmt::format("{:.1f} %", 100 * v);
}

const VariantColumn kColumns[] = {
    {"layers", "layers", [](double v) { return fmt::format("{:.0f}", v); }, false},
    {"print_time_s", "print time", hms},
    // A tenth of a kilogram at LSAM scale, three digits for a desktop part's grams.
    {"mass_kg", "mass kg",
     [](double v) { return v >= 1.0 ? fmt::format("{:.1f}", v) : fmt::format("{:.3g}", v); }},
    {"porosity", "porosity", [](double v) { return fmt::format("{:.2f} %", 100 * v); }},
    {"interfaces.too_hot_fraction", "too hot", percent},
    {"interfaces.too_cold_fraction", "too cold", percent},
    {"interfaces.min_healing", "min healing", [](double v) { return fmt::format("{:.3f}", v); }},
    {"layer_time_s.mean", "mean layer time s", [](double v) { return fmt::format("{:.0f}", v); }, false},
    {"min_stock_mm", "min stock mm", [](double v) { return fmt::format("{:.2f}", v); }},
};

}  // namespace

std::span<const VariantColumn> variant_columns() {
  return kColumns;
}

VariantCell variant_cell(const VariantColumn& c, const Metrics& m, const Metrics* baseline) {
  const MetricDef& d = metric_def(c.metric);
  const std::optional<double> value = d.read(m);
  if (!value || !std::isfinite(*value)) return {"—", {}, 0};
  VariantCell cell{c.text(*value), {}, 0};
  const std::optional<double> was = baseline ? d.read(*baseline) : std::nullopt;
  if (!was || !std::isfinite(*was)) return cell;
  const double change = *value - *was;
  const double scale = std::max(std::abs(*was), 1e-12);
  const bool fraction = d.unit == MetricUnit::kFraction;
  const bool differs = fraction ? std::abs(change) >= 5e-4 : std::abs(change) / scale >= 0.005;
  if (!differs) return cell;
  cell.delta =
      fraction ? fmt::format("{:+.1f} pt", 100 * change) : fmt::format("{:+.1f} %", 100 * change / scale);
  if (d.better != Better::kNeither) cell.judgement = (change > 0) == (d.better == Better::kHigher) ? +1 : -1;
  return cell;
}

}  // namespace beadtwin::scenarios
