// The metrics a gate may name, each once: its dotted name (as in report.json) and how to read it.
#include <algorithm>
#include <string_view>
#include <utility>

#include "core/error.hpp"
#include "scenarios/result.hpp"
#include "scenarios/scenario.hpp"

namespace beadtwin::scenarios {
namespace {

struct MetricDef {
  const char* name;
  std::optional<double> (*read)(const Metrics&);
};

std::optional<double> cad_metric(const Metrics& m, double CadMetrics::*field) {
  return m.cad ? std::optional<double>((*m.cad).*field) : std::nullopt;
}

const MetricDef kMetrics[] = {
    {"layers", [](const Metrics& m) -> std::optional<double> { return m.layers; }},
    {"print_time_s", [](const Metrics& m) -> std::optional<double> { return m.print_time_s; }},
    {"print_length_mm", [](const Metrics& m) -> std::optional<double> { return m.print_length_mm; }},
    {"travel_length_mm", [](const Metrics& m) -> std::optional<double> { return m.travel_length_mm; }},
    {"commanded_volume_mm3",
     [](const Metrics& m) -> std::optional<double> { return m.commanded_volume_mm3; }},
    {"deposited_volume_mm3",
     [](const Metrics& m) -> std::optional<double> { return m.deposited_volume_mm3; }},
    {"mass_kg", [](const Metrics& m) -> std::optional<double> { return m.mass_kg; }},
    {"material_cost", [](const Metrics& m) -> std::optional<double> { return m.material_cost; }},
    {"porosity", [](const Metrics& m) -> std::optional<double> { return m.porosity; }},
    {"min_stock_mm", [](const Metrics& m) { return m.min_stock_mm; }},
    {"undercut_fraction", [](const Metrics& m) { return m.undercut_fraction; }},
    // The rest of the part-versus-CAD comparison, unset like min_stock_mm when there is no CAD.
    {"max_stock_mm", [](const Metrics& m) { return cad_metric(m, &CadMetrics::max_stock_mm); }},
    {"mean_stock_mm", [](const Metrics& m) { return cad_metric(m, &CadMetrics::mean_stock_mm); }},
    {"below_requested_stock_fraction",
     [](const Metrics& m) { return cad_metric(m, &CadMetrics::below_requested_stock_fraction); }},
    {"deviation_rms_mm", [](const Metrics& m) { return cad_metric(m, &CadMetrics::deviation_rms_mm); }},
    {"machining_waste_fraction",
     [](const Metrics& m) { return cad_metric(m, &CadMetrics::machining_waste_fraction); }},
    {"interfaces.count", [](const Metrics& m) -> std::optional<double> { return m.interfaces; }},
    {"interfaces.too_hot_fraction",
     [](const Metrics& m) -> std::optional<double> { return m.too_hot_fraction; }},
    {"interfaces.too_cold_fraction",
     [](const Metrics& m) -> std::optional<double> { return m.too_cold_fraction; }},
    // Healing is measured at interfaces: a single-layer part has none.
    {"interfaces.min_healing",
     [](const Metrics& m) -> std::optional<double> {
       return m.interfaces > 0 ? std::optional<double>(m.min_healing) : std::nullopt;
     }},
    {"interfaces.mean_healing",
     [](const Metrics& m) -> std::optional<double> {
       return m.interfaces > 0 ? std::optional<double>(m.mean_healing) : std::nullopt;
     }},
    {"layer_time_s.min", [](const Metrics& m) -> std::optional<double> { return m.layer_time_s.min; }},
    {"layer_time_s.mean", [](const Metrics& m) -> std::optional<double> { return m.layer_time_s.mean; }},
    {"layer_time_s.max", [](const Metrics& m) -> std::optional<double> { return m.layer_time_s.max; }},
    {"extruder_demand", [](const Metrics& m) -> std::optional<double> { return m.extruder_demand; }},
    {"planned_voids", [](const Metrics& m) -> std::optional<double> { return m.planned_voids; }},
    {"planned_void_area_mm2",
     [](const Metrics& m) -> std::optional<double> { return m.planned_void_area_mm2; }},
    {"defects.voids", [](const Metrics& m) -> std::optional<double> { return m.voids; }},
    {"defects.void_volume_mm3", [](const Metrics& m) -> std::optional<double> { return m.void_volume_mm3; }},
    {"defects.plough_volume_mm3",
     [](const Metrics& m) -> std::optional<double> { return m.plough_volume_mm3; }},
    {"defects.unsupported_length_mm",
     [](const Metrics& m) -> std::optional<double> { return m.unsupported_length_mm; }},
    {"defects.roller_corners", [](const Metrics& m) -> std::optional<double> { return m.roller_corners; }},
    {"defects.collisions", [](const Metrics& m) -> std::optional<double> { return m.collisions; }},
    {"layer_fill.min", [](const Metrics& m) { return m.min_layer_fill; }},
    {"layer_fill.max", [](const Metrics& m) { return m.max_layer_fill; }},
};

// A section's figures, named as sections.NAME.FIGURE.
struct SectionMetricDef {
  const char* name;
  std::optional<double> (*read)(const SectionRow&);
};

const SectionMetricDef kSectionMetrics[] = {
    {"layers", [](const SectionRow& s) -> std::optional<double> { return s.layers; }},
    {"print_time_s", [](const SectionRow& s) -> std::optional<double> { return s.print_time_s; }},
    {"print_length_mm", [](const SectionRow& s) -> std::optional<double> { return s.print_length_mm; }},
    {"commanded_volume_mm3",
     [](const SectionRow& s) -> std::optional<double> { return s.commanded_volume_mm3; }},
    {"mass_kg", [](const SectionRow& s) -> std::optional<double> { return s.mass_kg; }},
    {"material_cost", [](const SectionRow& s) -> std::optional<double> { return s.material_cost; }},
    {"mean_layer_time_s", [](const SectionRow& s) -> std::optional<double> { return s.mean_layer_time_s; }},
    {"interfaces.count", [](const SectionRow& s) -> std::optional<double> { return s.interfaces; }},
    {"interfaces.too_hot_fraction",
     [](const SectionRow& s) -> std::optional<double> { return s.too_hot_fraction; }},
    {"interfaces.too_cold_fraction",
     [](const SectionRow& s) -> std::optional<double> { return s.too_cold_fraction; }},
    {"interfaces.min_healing",
     [](const SectionRow& s) -> std::optional<double> {
       return s.interfaces > 0 ? std::optional<double>(s.healing) : std::nullopt;
     }},
    {"interfaces.mean_healing",
     [](const SectionRow& s) -> std::optional<double> {
       return s.interfaces > 0 ? std::optional<double>(s.healing_mean) : std::nullopt;
     }},
};

constexpr std::string_view kSectionPrefix = "sections.";

// sections.NAME.FIGURE split into NAME and the figure's definition; nullopt for any other name.
std::optional<std::pair<std::string, const SectionMetricDef*>> split_section_metric(const std::string& name) {
  if (!name.starts_with(kSectionPrefix)) return std::nullopt;
  const std::string_view rest = std::string_view(name).substr(kSectionPrefix.size());
  for (const auto& d : kSectionMetrics) {
    const std::string suffix = std::string(".") + d.name;
    if (rest.size() > suffix.size() && rest.ends_with(suffix))
      return std::make_pair(std::string(rest.substr(0, rest.size() - suffix.size())), &d);
  }
  return std::nullopt;
}

}  // namespace

const std::vector<std::string>& section_gate_metrics() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const auto& d : kSectionMetrics) out.emplace_back(d.name);
    return out;
  }();
  return names;
}

bool is_gate_metric(const std::string& name) {
  const auto& top = gate_metrics();
  return std::find(top.begin(), top.end(), name) != top.end() || split_section_metric(name).has_value();
}

std::optional<std::string> gate_metric_section(const std::string& name) {
  if (const auto split = split_section_metric(name)) return split->first;
  return std::nullopt;
}

const std::vector<std::string>& gate_metrics() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const auto& d : kMetrics) out.emplace_back(d.name);
    return out;
  }();
  return names;
}

std::optional<double> Metrics::get(const std::string& name) const {
  for (const auto& d : kMetrics)
    if (name == d.name) return d.read(*this);
  if (const auto split = split_section_metric(name)) {
    for (const SectionRow& s : sections)
      if (s.name == split->first) return split->second->read(s);
    return std::nullopt;
  }
  throw InternalError("unknown metric " + name);
}

MetricValues Metrics::values() const {
  MetricValues out;
  for (const auto& d : kMetrics)
    if (const std::optional<double> v = d.read(*this)) out.emplace(d.name, *v);
  for (const SectionRow& s : sections)
    for (const auto& d : kSectionMetrics)
      if (const std::optional<double> v = d.read(s))
        out.emplace(std::string(kSectionPrefix) + s.name + "." + d.name, *v);
  return out;
}

}  // namespace beadtwin::scenarios
