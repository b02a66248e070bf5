#include "thermal/summary.hpp"

#include <algorithm>
#include <cmath>

namespace beadtwin::thermal {
namespace {

void add(FusionSummary& s, const InterfaceResult& r) {
  ++s.interfaces;
  s.area_mm2 += r.area_mm2;
  if (r.on_top) {
    s.substrate_min_c =
        std::isnan(s.substrate_min_c) ? r.substrate_c : std::min(s.substrate_min_c, r.substrate_c);
    s.substrate_max_c =
        std::isnan(s.substrate_max_c) ? r.substrate_c : std::max(s.substrate_max_c, r.substrate_c);
    // Kept as the area-weighted sum until finish().
    s.substrate_mean_c =
        (std::isnan(s.substrate_mean_c) ? 0.0 : s.substrate_mean_c) + r.area_mm2 * r.substrate_c;
  }
  s.healing_min = std::isnan(s.healing_min) ? r.healing : std::min(s.healing_min, r.healing);
  s.healing_mean = (std::isnan(s.healing_mean) ? 0.0 : s.healing_mean) + r.area_mm2 * r.healing;
  if (r.verdict == Verdict::kTooHot) {
    ++s.too_hot;
    s.too_hot_area_mm2 += r.area_mm2;
  } else if (r.verdict == Verdict::kTooCold) {
    ++s.too_cold;
    s.too_cold_area_mm2 += r.area_mm2;
  }
}

void finish(FusionSummary& s, double on_top_area_mm2) {
  if (!std::isnan(s.substrate_mean_c))
    s.substrate_mean_c = on_top_area_mm2 > 0.0 ? s.substrate_mean_c / on_top_area_mm2 : s.substrate_min_c;
  if (!std::isnan(s.healing_mean))
    s.healing_mean = s.area_mm2 > 0.0 ? s.healing_mean / s.area_mm2 : s.healing_min;
}

int severity(Verdict v) {
  switch (v) {
    case Verdict::kTooHot:
      return 3;
    case Verdict::kTooCold:
      return 2;
    case Verdict::kOk:
      return 1;
    case Verdict::kNoInterface:
      return 0;
  }
  return 0;
}

}  // namespace

Verdict FusionSummary::verdict() const {
  if (interfaces == 0) return Verdict::kNoInterface;
  if (std::max(too_hot_area_mm2, too_cold_area_mm2) < kVerdictShare * area_mm2) return Verdict::kOk;
  return too_hot_area_mm2 >= too_cold_area_mm2 ? Verdict::kTooHot : Verdict::kTooCold;
}

std::vector<FusionSummary> summarise_layers(const ThermalMesh& mesh, const HeatResult& heat,
                                            std::size_t layer_count) {
  std::vector<FusionSummary> layers(layer_count);
  std::vector<double> on_top_area(layer_count, 0.0);
  for (const InterfaceResult& r : heat.interfaces) {
    const int layer = mesh.cells[r.younger].layer;
    if (layer < 0 || static_cast<std::size_t>(layer) >= layer_count) continue;
    add(layers[static_cast<std::size_t>(layer)], r);
    if (r.on_top) on_top_area[static_cast<std::size_t>(layer)] += r.area_mm2;
  }
  for (std::size_t k = 0; k < layer_count; ++k) finish(layers[k], on_top_area[k]);
  return layers;
}

FusionSummary summarise_part(const HeatResult& heat) {
  FusionSummary s;
  double on_top_area = 0.0;
  for (const InterfaceResult& r : heat.interfaces) {
    add(s, r);
    if (r.on_top) on_top_area += r.area_mm2;
  }
  finish(s, on_top_area);
  return s;
}

std::vector<Verdict> cell_verdicts(const ThermalMesh& mesh, const HeatResult& heat) {
  std::vector<Verdict> out(mesh.cells.size(), Verdict::kNoInterface);
  for (const InterfaceResult& r : heat.interfaces)
    if (severity(r.verdict) > severity(out[r.younger])) out[r.younger] = r.verdict;
  return out;
}

}  // namespace beadtwin::thermal
