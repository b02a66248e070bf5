// What the interfaces of a heat solution add up to: per layer, for the whole part, per cell (for the fusion
// map drawn on the part).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "thermal/fusion.hpp"
#include "thermal/heat.hpp"
#include "thermal/mesh.hpp"

namespace beadtwin::thermal {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A temperature over interfaces, °C: least, area-weighted mean, most; NaN over none.
struct TemperatureStats {
  double min_c = kNaN, mean_c = kNaN, max_c = kNaN;
};

// The interfaces whose younger cell (the bead that landed) lies in one toolpath layer, or in the whole part.
struct FusionSummary {
  std::size_t interfaces = 0;
  double area_mm2 = 0.0;
  // Where beads landed on top of something (NaN where none did, as on the first layer): the substrate's
  // temperature (its cell's) and its surface's as the bead landed (InterfaceResult).
  TemperatureStats substrate, surface;
  // There too: the substrate temperature at which what was under the bead would just have carried it
  // (SupportResult::limit_c, where some temperature would not), and the most any of them slumped, as a
  // fraction of what is allowed (above 1: too hot); NaN where none landed on top.
  TemperatureStats support_limit;
  double slump_ratio_max = kNaN;
  // Degree of healing min(1, D_h): least and area-weighted mean; NaN without interfaces.
  double healing_min = kNaN, healing_mean = kNaN;
  std::size_t too_hot = 0, too_cold = 0;  // interfaces
  double too_hot_area_mm2 = 0.0, too_cold_area_mm2 = 0.0;
  double too_hot_fraction() const { return area_mm2 > 0.0 ? too_hot_area_mm2 / area_mm2 : 0.0; }
  double too_cold_fraction() const { return area_mm2 > 0.0 ? too_cold_area_mm2 / area_mm2 : 0.0; }
  // The bands over the inputs' plausible ranges (InterfaceResult; NaN where not estimated): the area-weighted
  // means of the interfaces' P10s and of their P90s (of the on-top ones for the temperatures). The inputs
  // move every interface the same way, so this is the band of the mean when they move together, and no
  // narrower than the linearised band of the mean otherwise.
  double substrate_p10_c = kNaN, substrate_p90_c = kNaN, surface_p10_c = kNaN, surface_p90_c = kNaN;
  double healing_p10 = kNaN, healing_p90 = kNaN;
  // Interfaces whose verdict changes within their bands (marginal) and their area; the area too hot or too
  // cold at the pessimistic end of each one's bands (p90: the hot end for too hot, the cold end for too
  // cold) and at the optimistic end (p10).
  std::size_t marginal = 0;
  double marginal_area_mm2 = 0.0;
  double too_hot_p90_area_mm2 = 0.0, too_hot_p10_area_mm2 = 0.0;
  double too_cold_p90_area_mm2 = 0.0, too_cold_p10_area_mm2 = 0.0;
  double share(double area) const { return area_mm2 > 0.0 ? area / area_mm2 : 0.0; }
  // The verdict as verdict() gives it from the pessimistic (p90) or the optimistic (p10) areas; marginal
  // when they differ from each other.
  Verdict verdict_at(bool pessimistic) const;
  bool marginal_verdict() const { return verdict_at(true) != verdict_at(false); }
  // Interfaces still at or above the healing threshold when the healing integral ended, and their area.
  std::size_t still_warm = 0;
  double still_warm_area_mm2 = 0.0;
  double still_warm_fraction() const { return area_mm2 > 0.0 ? still_warm_area_mm2 / area_mm2 : 0.0; }
  // The problem covering most of the interface area when at least `kVerdictShare` of it has one, else ok;
  // kNoInterface without interfaces.
  Verdict verdict() const;
  // Per layer: the layer times, s, that would have put it in the window (see layer_time_window), for all
  // but kVerdictShare of its landing area (the verdict's measure), and for half of it (the typical
  // interface); NaN where nothing bounds them, +infinity for a minimum no wait reaches. min > max: no layer
  // time would.
  double layer_time_min_s = kNaN, layer_time_max_s = kNaN;
  double typical_time_min_s = kNaN, typical_time_max_s = kNaN;
};
constexpr double kVerdictShare = 0.01;

// One summary per toolpath layer (by the younger cell's layer; cells outside [0, layer_count) are left out).
// `durations_s`: each layer's time as printed (for the layer-time window), `ambient_c` the air's.
std::vector<FusionSummary> summarise_layers(const ThermalMesh& mesh, const HeatResult& heat,
                                            std::span<const double> durations_s, const Material& material,
                                            double ambient_c);

// What a layer time L' would have done, as a change of the wait at the layer change (every interface where a
// bead lands on the layer below stands L' − L longer or shorter before it is covered; interfaces within the
// layer do not change). Per interface, from what the solution knows as the bead landed:
//  - the substrate cools on exponentially towards the air, T∞ + (T_s − T∞) exp(−w/τ), with τ = (T_s − T∞) /
//    (−dT_s/dt) from its cooling rate at that moment;
//  - the healing integral scales as the reptation time at the first contact temperature (T_dep + T_s)/2:
//    the history keeps its shape, shifted by the change of the contact temperature.
// The shortest layer time keeps `share` of the landing area at or below the support limit; the longest keeps
// `share` of it healing as required. Interfaces whose substrate was not cooling as it was covered (laid
// together with it, or just warmed by a neighbour) have no curve to follow and are left out. A first-order
// estimate: it says which way to move and about how far, not the exact layer time.
struct LayerTimeWindow {
  double min_s = kNaN, max_s = kNaN;
};
// `landing`: the layer's interfaces where a bead lands on the layer below; `duration_s` its layer time as
// printed, s; `ambient_c` the air's temperature, °C; `share` a fraction in (0, 1).
LayerTimeWindow layer_time_window(std::span<const InterfaceResult> landing, double duration_s,
                                  const Material& material, double ambient_c, double share);
// The whole part's summary: summarise_groups with every cell in one group.
FusionSummary summarise_part(const HeatResult& heat);
// One summary per group, by the group of the younger cell (`group_of_cell`, one entry per cell; a group
// outside [0, group_count) is left out): the sections of a print, say.
std::vector<FusionSummary> summarise_groups(const HeatResult& heat, std::span<const int> group_of_cell,
                                            std::size_t group_count);

// Per cell, its worst interface as the younger one (too hot before too cold before marginal before ok, an
// interface whose verdict changes within its bands counting as marginal); kNoInterface for a cell that landed
// on nothing but the table and touches nothing older.
std::vector<Verdict> cell_verdicts(const ThermalMesh& mesh, const HeatResult& heat);

// Per cell, the temperature of what it landed on as it was born, °C: the area-weighted mean substrate
// temperature of its interfaces as the younger cell that face up (HeatResult's on_top); NaN for a cell that
// landed on nothing older (the first layer on the table, a bead beside older ones only). `temperature`: the
// substrate's cell temperature, or its surface's (&InterfaceResult::substrate_surface_c).
std::vector<double> cell_substrate_c(const ThermalMesh& mesh, const HeatResult& heat,
                                     double InterfaceResult::*temperature = &InterfaceResult::substrate_c);

// Per cell, the least degree of healing of its interfaces as the younger cell (0..1); NaN for a cell with
// none, as in cell_verdicts.
std::vector<double> cell_healing(const ThermalMesh& mesh, const HeatResult& heat);

}  // namespace beadtwin::thermal
