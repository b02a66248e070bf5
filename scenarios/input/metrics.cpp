// The metrics, each declared once (scenarios/input/metrics.hpp), and what reads them by name.
#include "scenarios/input/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>
#include <type_traits>
#include <utility>

#include <fmt/format.h>

#include "core/error.hpp"
#include "scenarios/input/result.hpp"

namespace beadtwin::scenarios {
namespace {

using U = MetricUnit;
constexpr bool kGate = true, kDiagnostic = false;

template <class T>
std::optional<double> as_value(const T& v) {
  if constexpr (std::is_same_v<T, std::optional<double>>)
    return v;
  else
    return static_cast<double>(v);
}

// A member of the run's figures (Metrics) or of a section's (SectionRow, FusionRow).
template <auto Member>
std::optional<double> part(const Metrics& m) {
  return as_value(m.*Member);
}
template <auto Member>
std::optional<double> section(const SectionRow& s) {
  return as_value(s.*Member);
}
// The whole part's figures of its interfaces (Metrics::fusion); unset without interfaces.
template <auto Member>
std::optional<double> fusion(const Metrics& m) {
  return m.interfaces > 0 ? std::optional<double>(m.fusion.*Member) : std::nullopt;
}

template <double Stats3::*Member>
std::optional<double> layer_time(const Metrics& m) {
  return m.layer_time_s.*Member;
}
// The rest of the part-versus-CAD comparison, unset like min_stock_mm when there is no CAD.
template <double CadMetrics::*Member>
std::optional<double> cad(const Metrics& m) {
  return m.cad ? std::optional<double>((*m.cad).*Member) : std::nullopt;
}
// Healing is measured at interfaces: a single-layer part has none.
template <class Row, auto Member>
std::optional<double> healing(const Row& r) {
  return r.interfaces > 0 ? std::optional<double>(r.*Member) : std::nullopt;
}

// A figure that is not a number where nothing measured it: unset there.
template <class Row, double Row::*Member>
std::optional<double> finite(const Row& r) {
  return std::isfinite(r.*Member) ? std::optional<double>(r.*Member) : std::nullopt;
}

const MetricDef kMetrics[] = {
    {"layers", U::kCount, Better::kNeither, kGate, part<&Metrics::layers>, "layers in the toolpath"},
    {"print_time_s", U::kSeconds, Better::kLower, kGate, part<&Metrics::print_time_s>,
     "the head's time for the whole program: its moves, travels and dwells"},
    {"print_length_mm", U::kMm, Better::kNeither, kGate, part<&Metrics::print_length_mm>,
     "length of the moves that lay a bead"},
    {"travel_length_mm", U::kMm, Better::kLower, kGate, part<&Metrics::travel_length_mm>,
     "length of the moves that lay nothing"},
    {"commanded_volume_mm3", U::kMm3, Better::kNeither, kGate, part<&Metrics::commanded_volume_mm3>,
     "material the program asks the extruder for"},
    {"deposited_volume_mm3", U::kMm3, Better::kNeither, kGate, part<&Metrics::deposited_volume_mm3>,
     "material in the voxel model after the deposit"},
    {"mass_kg", U::kKg, Better::kLower, kGate, part<&Metrics::mass_kg>,
     "the deposited material at the material's density"},
    {"material_cost", U::kCurrency, Better::kLower, kGate, part<&Metrics::material_cost>,
     "the mass at the material's price per kg"},
    {"porosity", U::kFraction, Better::kLower, kGate, part<&Metrics::porosity>,
     "share of the printed envelope the beads leave empty"},
    {"min_stock_mm", U::kMm, Better::kHigher, kGate, part<&Metrics::min_stock_mm>,
     "least stock left for machining over the CAD surface; negative where the print falls short of it "
     "(measured with a CAD to compare with)"},
    {"undercut_fraction", U::kFraction, Better::kLower, kGate, part<&Metrics::undercut_fraction>,
     "share of the CAD surface where the print falls short of it (stock < 0)"},
    {"max_stock_mm", U::kMm, Better::kLower, kGate, cad<&CadMetrics::max_stock_mm>,
     "most stock over the CAD surface"},
    {"mean_stock_mm", U::kMm, Better::kNeither, kGate, cad<&CadMetrics::mean_stock_mm>,
     "stock over the CAD surface, area-weighted mean"},
    {"below_requested_stock_fraction", U::kFraction, Better::kLower, kGate,
     cad<&CadMetrics::below_requested_stock_fraction>,
     "share of the CAD surface with less stock than the sections ask for"},
    {"deviation_rms_mm", U::kMm, Better::kLower, kGate, cad<&CadMetrics::deviation_rms_mm>,
     "the printed skin's distance from the CAD, root mean square over the skin"},
    {"machining_waste_fraction", U::kFraction, Better::kLower, kGate,
     cad<&CadMetrics::machining_waste_fraction>,
     "material outside the CAD (what machining removes) as a share of the deposit"},
    {"interfaces.count", U::kCount, Better::kNeither, kGate, part<&Metrics::interfaces>,
     "interfaces where a bead landed on an older one"},
    {"interfaces.too_hot_fraction", U::kFraction, Better::kLower, kGate, part<&Metrics::too_hot_fraction>,
     "share of the interface area too hot: where the soft material under the bead slumps under it and the "
     "roller by more than the material allows"},
    {"interfaces.max_slump_ratio", U::kRatio, Better::kLower, kGate,
     finite<Metrics, &Metrics::max_slump_ratio>,
     "the most the soft material under a landing bead slumped, over what the material allows (above 1: too "
     "hot; unset where no bead landed on another)"},
    {"interfaces.too_cold_fraction", U::kFraction, Better::kLower, kGate, part<&Metrics::too_cold_fraction>,
     "share of the interface area that does not heal"},
    {"interfaces.too_cold_fraction_p90", U::kFraction, Better::kLower, kGate,
     fusion<&FusionRow::too_cold_fraction_p90>,
     "share of the interface area too cold at the cold end of each interface's P10-P90 band over the inputs' "
     "plausible ranges (thermal.uncertainty; the pessimistic too_cold_fraction, equal to it when off)"},
    {"interfaces.too_cold_fraction_p10", U::kFraction, Better::kLower, kGate,
     fusion<&FusionRow::too_cold_fraction_p10>,
     "share of the interface area too cold even at the warm end of each one's band (the optimistic "
     "too_cold_fraction)"},
    {"interfaces.too_hot_fraction_p90", U::kFraction, Better::kLower, kGate,
     fusion<&FusionRow::too_hot_fraction_p90>,
     "share of the interface area too hot at the hot end of each one's band (the pessimistic "
     "too_hot_fraction)"},
    {"interfaces.too_hot_fraction_p10", U::kFraction, Better::kLower, kGate,
     fusion<&FusionRow::too_hot_fraction_p10>,
     "share of the interface area too hot even at the cool end of each one's band (the optimistic "
     "too_hot_fraction)"},
    {"interfaces.marginal_fraction", U::kFraction, Better::kLower, kGate,
     fusion<&FusionRow::marginal_fraction>,
     "share of the interface area whose verdict changes within its P10-P90 band (marginal; 0 without "
     "thermal.uncertainty)"},
    {"interfaces.min_healing", U::kRatio, Better::kHigher, kGate, healing<Metrics, &Metrics::min_healing>,
     "least degree of healing over the interfaces (1: fully healed; unset without interfaces)"},
    {"interfaces.mean_healing", U::kRatio, Better::kHigher, kGate, healing<Metrics, &Metrics::mean_healing>,
     "degree of healing, area-weighted mean over the interfaces"},
    {"interfaces.still_warm_fraction", U::kFraction, Better::kLower, kGate,
     part<&Metrics::still_warm_fraction>,
     "share of the interface area still at or above the healing threshold when the healing integral ended "
     "(thermal.max_cooldown after the last layer): healing there is what it had reached by then"},
    {"layer_time_s.min", U::kSeconds, Better::kNeither, kGate, layer_time<&Stats3::min>,
     "shortest layer time"},
    {"layer_time_s.mean", U::kSeconds, Better::kNeither, kGate, layer_time<&Stats3::mean>, "mean layer time"},
    {"layer_time_s.max", U::kSeconds, Better::kNeither, kGate, layer_time<&Stats3::max>,
     "longest layer time"},
    {"extruder_demand", U::kRatio, Better::kLower, kGate, part<&Metrics::extruder_demand>,
     "the most any move asks of the extruder over its limit (max flow or max RPM); above 1 it needs more "
     "than "
     "the extruder gives"},
    {"planned_voids", U::kCount, Better::kLower, kGate, part<&Metrics::planned_voids>,
     "uncovered pieces the slicer found (sections with voids.detect)"},
    {"planned_void_area_mm2", U::kMm2, Better::kLower, kGate, part<&Metrics::planned_void_area_mm2>,
     "their area"},
    {"defects.voids", U::kCount, Better::kLower, kGate, part<&Metrics::voids>,
     "voids of at least a voxel the deposit found inside the part"},
    {"defects.void_volume_mm3", U::kMm3, Better::kLower, kGate, part<&Metrics::void_volume_mm3>,
     "empty volume inside the printed envelope"},
    {"defects.plough_volume_mm3", U::kMm3, Better::kLower, kGate, part<&Metrics::plough_volume_mm3>,
     "material the roller ploughed aside"},
    {"defects.unsupported_length_mm", U::kMm, Better::kLower, kGate, part<&Metrics::unsupported_length_mm>,
     "bead laid over nothing"},
    {"defects.roller_corners", U::kCount, Better::kLower, kGate, part<&Metrics::roller_corners>,
     "corners too tight for the roller to follow"},
    {"defects.collisions", U::kCount, Better::kLower, kGate, part<&Metrics::collisions>,
     "the nozzle or the roller running into the part"},
    {"layer_fill.min", U::kRatio, Better::kNeither, kGate, part<&Metrics::min_layer_fill>,
     "lowest layer fill: a layer's commanded material over its outline times its height (1: exactly full)"},
    {"layer_fill.max", U::kRatio, Better::kNeither, kGate, part<&Metrics::max_layer_fill>,
     "highest layer fill"},
    {"deposit.voxel_size_mm", U::kMm, Better::kNeither, kDiagnostic, part<&Metrics::voxel_size_mm>,
     "edge of the deposit's voxels"},
    {"deposit.voxels", U::kCount, Better::kNeither, kDiagnostic, part<&Metrics::voxels>,
     "voxels holding material"},
    {"deposit.swept_volume_mm3", U::kMm3, Better::kNeither, kDiagnostic, part<&Metrics::swept_volume_mm3>,
     "volume of the swept bead shapes, before the deposit conserves the commanded material"},
    {"deposit.redistributed_volume_mm3", U::kMm3, Better::kNeither, kDiagnostic,
     part<&Metrics::redistributed_volume_mm3>, "material pushed out of full voxels into free neighbours"},
    {"thermal.energy_balance_rel_error", U::kRatio, Better::kLower, kDiagnostic,
     part<&Metrics::thermal_energy_error>, "the thermal solution's energy balance error, relative"},
    {"thermal.cvode_steps", U::kCount, Better::kNeither, kDiagnostic, part<&Metrics::thermal_steps>,
     "time steps the thermal solver took"},
    {"thermal.healing_followed_s", U::kSeconds, Better::kNeither, kDiagnostic,
     part<&Metrics::healing_followed_s>,
     "how long after the last layer the healing integral was followed: the cooldown, or longer while an "
     "interface stayed at or above its healing threshold"},
};

const SectionMetricDef kSectionMetrics[] = {
    {"layers", U::kCount, Better::kNeither, kGate, section<&SectionRow::layers>, "the section's layers"},
    {"print_time_s", U::kSeconds, Better::kLower, kGate, section<&SectionRow::print_time_s>,
     "the head's time in the section, its moves, travels and dwells"},
    {"print_length_mm", U::kMm, Better::kNeither, kGate, section<&SectionRow::print_length_mm>,
     "length of its beads"},
    {"commanded_volume_mm3", U::kMm3, Better::kNeither, kGate, section<&SectionRow::commanded_volume_mm3>,
     "material its program asks for"},
    {"mass_kg", U::kKg, Better::kLower, kGate, section<&SectionRow::mass_kg>,
     "that material at the material's density"},
    {"material_cost", U::kCurrency, Better::kLower, kGate, section<&SectionRow::material_cost>,
     "its mass at the material's price per kg"},
    {"mean_layer_time_s", U::kSeconds, Better::kNeither, kGate, section<&SectionRow::mean_layer_time_s>,
     "mean time of its layers"},
    {"interfaces.count", U::kCount, Better::kNeither, kGate, section<&SectionRow::interfaces>,
     "interfaces where its beads landed on older ones"},
    {"interfaces.too_hot_fraction", U::kFraction, Better::kLower, kGate,
     section<&SectionRow::too_hot_fraction>,
     "share of their area too hot: where the soft material under the bead slumps"},
    {"interfaces.too_cold_fraction", U::kFraction, Better::kLower, kGate,
     section<&SectionRow::too_cold_fraction>, "share of their area that does not heal"},
    {"interfaces.min_healing", U::kRatio, Better::kHigher, kGate, healing<SectionRow, &SectionRow::healing>,
     "least degree of healing over them (unset without interfaces)"},
    {"interfaces.mean_healing", U::kRatio, Better::kHigher, kGate,
     healing<SectionRow, &SectionRow::healing_mean>, "degree of healing, area-weighted mean over them"},
    {"interfaces.too_cold_fraction_p90", U::kFraction, Better::kLower, kGate,
     section<&SectionRow::too_cold_fraction_p90>,
     "share of their area too cold at the cold end of each one's P10-P90 band"},
    {"interfaces.marginal_fraction", U::kFraction, Better::kLower, kGate,
     section<&SectionRow::marginal_fraction>, "share of their area whose verdict changes within its band"},
};

constexpr std::string_view kSectionPrefix = "sections.";

// sections.NAME.FIGURE split into NAME and the figure's declaration; nullopt for any other name.
std::optional<std::pair<std::string, const SectionMetricDef*>> split_section_metric(const std::string& name) {
  if (!name.starts_with(kSectionPrefix)) return std::nullopt;
  const std::string_view rest = std::string_view(name).substr(kSectionPrefix.size());
  for (const auto& d : kSectionMetrics) {
    const std::string suffix = fmt::format(".{}", d.name);
    if (rest.size() > suffix.size() && rest.ends_with(suffix))
      return std::make_pair(std::string(rest.substr(0, rest.size() - suffix.size())), &d);
  }
  return std::nullopt;
}

// The names of the declarations that gates may use.
template <class Row>
std::vector<std::string> gate_names(std::span<const MetricDecl<Row>> defs) {
  std::vector<std::string> out;
  for (const auto& d : defs)
    if (d.gate) out.emplace_back(d.name);
  return out;
}

template <class Row>
void markdown_table(std::string& out, std::span<const MetricDecl<Row>> defs, std::string_view prefix) {
  out += "| metric | unit | better | gates | meaning |\n|---|---|---|---|---|\n";
  for (const auto& d : defs)
    out += fmt::format("| `{}{}` | {} | {} | {} | {} |\n", prefix, d.name, to_string(d.unit),
                       to_string(d.better), d.gate ? "yes" : "no", d.meaning);
}

}  // namespace

std::string_view to_string(MetricUnit unit) {
  switch (unit) {
    case MetricUnit::kCount:
      return "count";
    case MetricUnit::kSeconds:
      return "s";
    case MetricUnit::kMm:
      return "mm";
    case MetricUnit::kMm2:
      return "mm²";
    case MetricUnit::kMm3:
      return "mm³";
    case MetricUnit::kKg:
      return "kg";
    case MetricUnit::kCurrency:
      return "currency";
    case MetricUnit::kFraction:
      return "fraction";
    case MetricUnit::kRatio:
      return "ratio";
  }
  return "?";
}

std::string_view to_string(Better better) {
  switch (better) {
    case Better::kNeither:
      return "–";
    case Better::kLower:
      return "lower";
    case Better::kHigher:
      return "higher";
  }
  return "?";
}

std::span<const MetricDef> metric_defs() {
  return kMetrics;
}

std::span<const SectionMetricDef> section_metric_defs() {
  return kSectionMetrics;
}

const MetricDef& metric_def(std::string_view name) {
  for (const MetricDef& d : kMetrics)
    if (d.name == name) return d;
  throw InternalError(fmt::format("undeclared metric {}", name));
}

const std::vector<std::string>& gate_metrics() {
  static const std::vector<std::string> names = gate_names(metric_defs());
  return names;
}

const std::vector<std::string>& section_gate_metrics() {
  static const std::vector<std::string> names = gate_names(section_metric_defs());
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

std::string unknown_metric_message(const std::string& name) {
  return fmt::format("unknown metric '{}'; expected one of: {}; or sections.NAME. and one of: {}", name,
                     fmt::join(gate_metrics(), ", "), fmt::join(section_gate_metrics(), ", "));
}

std::optional<double> Metrics::get(const std::string& name) const {
  for (const MetricDef& d : kMetrics)
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
  for (const MetricDef& d : kMetrics) {
    if (!d.gate) continue;
    if (const std::optional<double> v = d.read(*this)) out.emplace(d.name, *v);
  }
  for (const SectionRow& s : sections)
    for (const SectionMetricDef& d : kSectionMetrics)
      if (const std::optional<double> v = d.read(s))
        out.emplace(fmt::format("{}{}.{}", kSectionPrefix, s.name, d.name), *v);
  return out;
}

std::string metrics_markdown() {
  std::string out =
      "# Metrics\n\n"
      "Generated by `beadtwin metrics` from the one list the reports, the sweeps and the gate parser read, "
      "so\n"
      "it cannot drift from what beadtwin measures. A gate names a metric as below (`porosity < 0.03`,\n"
      "`interfaces.min_healing >= baseline`). report.json keeps every metric in a variant's `metrics` at "
      "its\n"
      "dotted path (`interfaces.count` is `metrics.interfaces.count`), null where it was not measured, and\n"
      "the gate metrics measured in `values` by their names, as a sweep gathers them. Better says which way\n"
      "the reports mark a change from the baseline variant as an improvement; a fraction's differences are\n"
      "given in points.\n\n"
      "## The part\n\n";
  markdown_table(out, metric_defs(), "");
  out +=
      "\n## Each section\n\n"
      "A section's figures, each a gate metric named `sections.NAME.FIGURE` with the section's name\n"
      "(`sections.walls.print_time_s`); report.json lists them in a variant's `sections`.\n\n";
  markdown_table(out, section_metric_defs(), "sections.NAME.");
  return out;
}

}  // namespace beadtwin::scenarios
