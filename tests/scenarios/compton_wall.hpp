// The shipped Compton wall (scenarios/data/compton-wall.yaml) as the tests cut and read it: the scenario, the
// wall cut to its first layers, the first bead of a layer and a sampled history read between its samples.
// Shared by the wall's own tests (compton_wall_test.cpp) and the comparisons with published evidence
// (validation_test.cpp).
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/toolpath.hpp"
#include "scenarios/input/embedded.hpp"
#include "scenarios/input/scenario.hpp"

namespace beadtwin::testing {

inline scenarios::Scenario compton_scenario() {
  return scenarios::load_scenario_text(scenarios::shipped_files().at("compton-wall.yaml"),
                                       "<built-in>/compton-wall.yaml");
}

// The wall cut to its first `layers` layers.
inline void keep_layers(scenarios::Variant& v, int layers) {
  slicer::SectionParams& wall = v.sections.at(0);
  wall.z_max_mm = wall.z_min_mm + layers * wall.layer_height_mm;
}

// The first move of a layer that lays material (a layer's moves start with the travel to it).
inline const Move& first_deposit(const Toolpath& tp, std::size_t layer) {
  const ToolpathLayer& l = tp.layers.at(layer);
  for (std::size_t m = l.first_move; m < l.end_move; ++m)
    if (tp.moves[m].deposits()) return tp.moves[m];
  throw InternalError(fmt::format("layer {} lays nothing", layer));
}

// A sampled history at t, linear between samples; NaN outside it or before the layer exists.
inline double at_time(const std::vector<double>& times, const std::vector<float>& values, double t) {
  if (times.empty() || t < times.front() || t > times.back()) return std::numeric_limits<double>::quiet_NaN();
  const auto k = static_cast<std::size_t>(std::upper_bound(times.begin(), times.end(), t) - times.begin());
  if (k == times.size()) return values.back();
  const double w = (t - times[k - 1]) / (times[k] - times[k - 1]);
  return (1.0 - w) * values[k - 1] + w * values[k];
}

}  // namespace beadtwin::testing
