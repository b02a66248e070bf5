// What the interfaces of a heat solution add up to: per layer, for the whole part, per cell (for the fusion
// map drawn on the part).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "thermal/fusion.hpp"
#include "thermal/heat.hpp"
#include "thermal/mesh.hpp"

namespace beadtwin::thermal {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The interfaces whose younger cell (the bead that landed) lies in one toolpath layer, or in the whole part.
struct FusionSummary {
  std::size_t interfaces = 0;
  double area_mm2 = 0.0;
  // The substrate's temperature where beads landed on top of it, °C: least, area-weighted mean, most; NaN
  // where no bead landed on top of anything (the first layer).
  double substrate_min_c = kNaN, substrate_mean_c = kNaN, substrate_max_c = kNaN;
  // Degree of healing min(1, D_h): least and area-weighted mean; NaN without interfaces.
  double healing_min = kNaN, healing_mean = kNaN;
  std::size_t too_hot = 0, too_cold = 0;  // interfaces
  double too_hot_area_mm2 = 0.0, too_cold_area_mm2 = 0.0;
  double too_hot_fraction() const { return area_mm2 > 0.0 ? too_hot_area_mm2 / area_mm2 : 0.0; }
  double too_cold_fraction() const { return area_mm2 > 0.0 ? too_cold_area_mm2 / area_mm2 : 0.0; }
  // The problem covering most of the interface area when at least `kVerdictShare` of it has one, else ok;
  // kNoInterface without interfaces.
  Verdict verdict() const;
};
constexpr double kVerdictShare = 0.01;

// One summary per toolpath layer (by the younger cell's layer; cells outside [0, layer_count) are left out).
std::vector<FusionSummary> summarise_layers(const ThermalMesh& mesh, const HeatResult& heat,
                                            std::size_t layer_count);
FusionSummary summarise_part(const HeatResult& heat);

// Per cell, its worst interface as the younger one (too hot before too cold before ok); kNoInterface for a
// cell that landed on nothing but the table and touches nothing older.
std::vector<Verdict> cell_verdicts(const ThermalMesh& mesh, const HeatResult& heat);

}  // namespace beadtwin::thermal
