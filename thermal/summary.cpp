#include "thermal/summary.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace beadtwin::thermal {
namespace {

// Adds `temp_c` over `area_mm2`; the mean is kept as the area-weighted sum until finish().
void add(TemperatureStats& s, double temp_c, double area_mm2) {
  s.min_c = std::isnan(s.min_c) ? temp_c : std::min(s.min_c, temp_c);
  s.max_c = std::isnan(s.max_c) ? temp_c : std::max(s.max_c, temp_c);
  s.mean_c = (std::isnan(s.mean_c) ? 0.0 : s.mean_c) + area_mm2 * temp_c;
}

void finish(TemperatureStats& s, double area_mm2) {
  if (!std::isnan(s.mean_c)) s.mean_c = area_mm2 > 0.0 ? s.mean_c / area_mm2 : s.min_c;
}

// Adds `value` over `area_mm2` to the area-weighted sum `sum` (NaN until the first; NaN values left out).
void add_weighted(double& sum, double value, double area_mm2) {
  if (!std::isnan(value)) sum = (std::isnan(sum) ? 0.0 : sum) + area_mm2 * value;
}

void add_bands(FusionSummary& s, const InterfaceResult& r) {
  if (r.on_top) {
    add_weighted(s.substrate_p10_c, r.substrate_p10_c, r.area_mm2);
    add_weighted(s.substrate_p90_c, r.substrate_p90_c, r.area_mm2);
    add_weighted(s.surface_p10_c, r.surface_p10_c, r.area_mm2);
    add_weighted(s.surface_p90_c, r.surface_p90_c, r.area_mm2);
  }
  add_weighted(s.healing_p10, r.healing_p10, r.area_mm2);
  add_weighted(s.healing_p90, r.healing_p90, r.area_mm2);
  if (r.marginal()) {
    ++s.marginal;
    s.marginal_area_mm2 += r.area_mm2;
  }
  // Too hot at the hot end, too cold at the cold end: the pessimistic ends; the other two the optimistic.
  s.too_hot_p90_area_mm2 += r.verdict_hot == Verdict::kTooHot ? r.area_mm2 : 0.0;
  s.too_hot_p10_area_mm2 += r.verdict_cold == Verdict::kTooHot ? r.area_mm2 : 0.0;
  s.too_cold_p90_area_mm2 += r.verdict_cold == Verdict::kTooCold ? r.area_mm2 : 0.0;
  s.too_cold_p10_area_mm2 += r.verdict_hot == Verdict::kTooCold ? r.area_mm2 : 0.0;
}

void add(FusionSummary& s, const InterfaceResult& r) {
  ++s.interfaces;
  s.area_mm2 += r.area_mm2;
  if (r.on_top) {
    add(s.substrate, r.substrate_c, r.area_mm2);
    add(s.surface, r.substrate_surface_c, r.area_mm2);
    if (std::isfinite(r.support.limit_c)) add(s.support_limit, r.support.limit_c, r.area_mm2);
    if (r.support.allowed_mm > 0.0)
      s.slump_ratio_max = std::fmax(s.slump_ratio_max, r.support.slump_mm / r.support.allowed_mm);
  }
  add_bands(s, r);
  s.healing_min = std::isnan(s.healing_min) ? r.healing : std::min(s.healing_min, r.healing);
  s.healing_mean = (std::isnan(s.healing_mean) ? 0.0 : s.healing_mean) + r.area_mm2 * r.healing;
  if (r.still_warm) {
    ++s.still_warm;
    s.still_warm_area_mm2 += r.area_mm2;
  }
  if (r.verdict == Verdict::kTooHot) {
    ++s.too_hot;
    s.too_hot_area_mm2 += r.area_mm2;
  } else if (r.verdict == Verdict::kTooCold) {
    ++s.too_cold;
    s.too_cold_area_mm2 += r.area_mm2;
  }
}

void finish(FusionSummary& s, double on_top_area_mm2, double limited_area_mm2) {
  finish(s.substrate, on_top_area_mm2);
  finish(s.surface, on_top_area_mm2);
  finish(s.support_limit, limited_area_mm2);
  for (double* t : {&s.substrate_p10_c, &s.substrate_p90_c, &s.surface_p10_c, &s.surface_p90_c})
    if (!std::isnan(*t)) *t = on_top_area_mm2 > 0.0 ? *t / on_top_area_mm2 : kNaN;
  for (double* h : {&s.healing_p10, &s.healing_p90})
    if (!std::isnan(*h)) *h = s.area_mm2 > 0.0 ? *h / s.area_mm2 : kNaN;
  if (!std::isnan(s.healing_mean))
    s.healing_mean = s.area_mm2 > 0.0 ? s.healing_mean / s.area_mm2 : s.healing_min;
}

int severity(Verdict v) {
  switch (v) {
    case Verdict::kTooHot:
      return 4;
    case Verdict::kTooCold:
      return 3;
    case Verdict::kMarginal:
      return 2;
    case Verdict::kOk:
      return 1;
    case Verdict::kNoInterface:
      return 0;
  }
  return 0;
}

}  // namespace

namespace {

Verdict verdict_of(const FusionSummary& s, double too_hot_mm2, double too_cold_mm2) {
  if (s.interfaces == 0) return Verdict::kNoInterface;
  if (std::max(too_hot_mm2, too_cold_mm2) < kVerdictShare * s.area_mm2) return Verdict::kOk;
  return too_hot_mm2 >= too_cold_mm2 ? Verdict::kTooHot : Verdict::kTooCold;
}

}  // namespace

Verdict FusionSummary::verdict() const {
  return verdict_of(*this, too_hot_area_mm2, too_cold_area_mm2);
}

Verdict FusionSummary::verdict_at(bool pessimistic) const {
  return pessimistic ? verdict_of(*this, too_hot_p90_area_mm2, too_cold_p90_area_mm2)
                     : verdict_of(*this, too_hot_p10_area_mm2, too_cold_p10_area_mm2);
}

std::vector<FusionSummary> summarise_layers(const ThermalMesh& mesh, const HeatResult& heat,
                                            std::span<const double> durations_s, const Material& material,
                                            double ambient_c) {
  const std::size_t layer_count = durations_s.size();
  std::vector<int> layer_of_cell;
  layer_of_cell.reserve(mesh.cells.size());
  for (const ThermalCell& c : mesh.cells) layer_of_cell.push_back(c.layer);
  std::vector<FusionSummary> layers = summarise_groups(heat, layer_of_cell, layer_count);
  // Where beads landed on the layer below: what a change of layer time acts on.
  std::vector<std::vector<InterfaceResult>> landing(layer_count);
  for (const InterfaceResult& r : heat.interfaces) {
    const int layer = layer_of_cell[r.younger];
    if (r.on_top && layer >= 0 && static_cast<std::size_t>(layer) < layer_count &&
        layer_of_cell[r.older] != layer)
      landing[static_cast<std::size_t>(layer)].push_back(r);
  }
  for (std::size_t k = 0; k < layer_count; ++k) {
    const LayerTimeWindow w =
        layer_time_window(landing[k], durations_s[k], material, ambient_c, 1.0 - kVerdictShare);
    layers[k].layer_time_min_s = w.min_s;
    layers[k].layer_time_max_s = w.max_s;
    const LayerTimeWindow typical = layer_time_window(landing[k], durations_s[k], material, ambient_c, 0.5);
    layers[k].typical_time_min_s = typical.min_s;
    layers[k].typical_time_max_s = typical.max_s;
  }
  return layers;
}

namespace {

// The wait w (s, either sign) at which the extra cooling `(T_s − T∞) exp(−w/τ)` brings a substrate at
// `from_c` to `to_c`; +infinity when it never gets there by waiting (not cooling, or `to_c` at or below the
// air), -infinity when no shorter wait makes it hot enough (`to_c` above the deposition temperature).
double wait_to_reach(double from_c, double to_c, double rate_K_s, double ambient_c, double deposition_c) {
  if (to_c > deposition_c) return -std::numeric_limits<double>::infinity();
  if (to_c <= ambient_c || !(rate_K_s < 0.0) || from_c <= ambient_c)
    return std::numeric_limits<double>::infinity();
  const double tau = (from_c - ambient_c) / -rate_K_s;
  return tau * std::log((from_c - ambient_c) / (to_c - ambient_c));
}

// The value below which `share` of the total weight lies (the lowest weighted quantile).
double weighted_quantile(std::vector<std::pair<double, double>> value_weight, double share) {
  if (value_weight.empty()) return kNaN;
  std::sort(value_weight.begin(), value_weight.end());
  double total = 0.0;
  for (const auto& [v, w] : value_weight) total += w;
  double sum = 0.0;
  for (const auto& [v, w] : value_weight) {
    sum += w;
    if (sum >= share * total) return v;
  }
  return value_weight.back().first;
}

}  // namespace

LayerTimeWindow layer_time_window(std::span<const InterfaceResult> landing, double duration_s,
                                  const Material& material, double ambient_c, double share) {
  const Reptation reptation(material);
  std::vector<std::pair<double, double>> hot, cold;  // (wait, area)
  for (const InterfaceResult& r : landing) {
    // The bead as it landed: the deposition temperature, or the program's nozzle temperature for it.
    const double t_dep = std::isfinite(r.bead_c) ? r.bead_c : material.deposition_temp_c;
    // Laid together with the bead on it (no layer change between them), or warming as it was covered (a
    // neighbour laid just before): no cooling curve to follow.
    if (!(r.substrate_rate_K_s < 0.0)) continue;
    // Too hot unless the substrate is at or below the temperature at which what is under it carries the
    // bead (thermal/support.hpp; infinite where no temperature up to the deposition's would slump it).
    hot.emplace_back(wait_to_reach(r.substrate_c, r.support.limit_c, r.substrate_rate_K_s, ambient_c, t_dep),
                     r.area_mm2);
    // Healing: the substrate temperature that would give the required D_h.
    double needed_c = t_dep;  // nothing healed at all: only the hottest substrate might
    if (r.healing_integral > 0.0) {
      // The integral needs to be D^4 / I times what it was: t_w at the needed contact temperature that
      // many times shorter than at the one it had.
      const double contact_c = 0.5 * (t_dep + r.substrate_c);
      const double needed_contact_c =
          reptation.temp_at_log_time(reptation.log_time(contact_c) -
                                     std::log(std::pow(material.required_healing, 4) / r.healing_integral));
      needed_c = std::isfinite(needed_contact_c) ? 2.0 * needed_contact_c - t_dep : t_dep + 1.0;
    }
    cold.emplace_back(wait_to_reach(r.substrate_c, needed_c, r.substrate_rate_K_s, ambient_c, t_dep),
                      r.area_mm2);
  }
  LayerTimeWindow w;
  if (hot.empty()) return w;
  // The shortest: the wait 99 % of the landing area needs to be cool enough; the longest: the wait at which
  // the most demanding 1 % stops healing.
  const double need = weighted_quantile(hot, share);
  const double allow = weighted_quantile(cold, 1.0 - share);
  if (std::isfinite(need)) w.min_s = std::max(0.0, duration_s + need);
  if (std::isfinite(allow)) w.max_s = std::max(0.0, duration_s + allow);
  if (need == std::numeric_limits<double>::infinity()) w.min_s = std::numeric_limits<double>::infinity();
  if (allow == -std::numeric_limits<double>::infinity()) w.max_s = 0.0;
  return w;
}

FusionSummary summarise_part(const HeatResult& heat) {
  std::size_t cells = 0;
  for (const InterfaceResult& r : heat.interfaces) cells = std::max<std::size_t>(cells, r.younger + 1);
  return summarise_groups(heat, std::vector<int>(cells, 0), 1).front();
}

std::vector<FusionSummary> summarise_groups(const HeatResult& heat, std::span<const int> group_of_cell,
                                            std::size_t group_count) {
  std::vector<FusionSummary> groups(group_count);
  std::vector<double> on_top_area(group_count, 0.0), limited_area(group_count, 0.0);
  for (const InterfaceResult& r : heat.interfaces) {
    const int g = group_of_cell[r.younger];
    if (g < 0 || static_cast<std::size_t>(g) >= group_count) continue;
    add(groups[static_cast<std::size_t>(g)], r);
    if (r.on_top) on_top_area[static_cast<std::size_t>(g)] += r.area_mm2;
    if (r.on_top && std::isfinite(r.support.limit_c)) limited_area[static_cast<std::size_t>(g)] += r.area_mm2;
  }
  for (std::size_t k = 0; k < group_count; ++k) finish(groups[k], on_top_area[k], limited_area[k]);
  return groups;
}

std::vector<Verdict> cell_verdicts(const ThermalMesh& mesh, const HeatResult& heat) {
  std::vector<Verdict> out(mesh.cells.size(), Verdict::kNoInterface);
  for (const InterfaceResult& r : heat.interfaces) {
    const Verdict v = r.marginal() ? Verdict::kMarginal : r.verdict;
    if (severity(v) > severity(out[r.younger])) out[r.younger] = v;
  }
  return out;
}

std::vector<double> cell_substrate_c(const ThermalMesh& mesh, const HeatResult& heat,
                                     double InterfaceResult::*temperature) {
  std::vector<double> sum(mesh.cells.size(), 0.0), area(mesh.cells.size(), 0.0);
  for (const InterfaceResult& r : heat.interfaces) {
    if (!r.on_top) continue;
    sum[r.younger] += r.area_mm2 * r.*temperature;
    area[r.younger] += r.area_mm2;
  }
  std::vector<double> out(mesh.cells.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < out.size(); ++i)
    if (area[i] > 0.0) out[i] = sum[i] / area[i];
  return out;
}

std::vector<double> cell_healing(const ThermalMesh& mesh, const HeatResult& heat) {
  std::vector<double> out(mesh.cells.size(), std::numeric_limits<double>::quiet_NaN());
  for (const InterfaceResult& r : heat.interfaces)
    if (!(out[r.younger] <= r.healing)) out[r.younger] = r.healing;  // NaN compares false: taken
  return out;
}

}  // namespace beadtwin::thermal
