// The scenario's gates judged on what a run measured: each gate's value, threshold and whether it passed,
// with a message naming the metric when it did not.
#pragma once

#include <cstddef>
#include <vector>

#include "scenarios/input/result.hpp"

namespace beadtwin::scenarios {

// Each of `gates` judged on `metrics`. `baseline`: the baseline variant's metrics, for the gates relative
// to it (null: such a gate fails, saying there is no baseline). A gate on a metric not measured fails,
// saying so (and, for a section's figure, which sections the run has).
std::vector<GateResult> evaluate_gates(const std::vector<Gate>& gates, const Metrics& metrics,
                                       const Metrics* baseline = nullptr);
// The same over measured values (Metrics::values), as a sweep gathers them from its variants' reports.
std::vector<GateResult> evaluate_gates(const std::vector<Gate>& gates, const MetricValues& values,
                                       const MetricValues* baseline = nullptr);

// The variant the relative gates compare with: the one named "baseline", else the first.
std::size_t baseline_index(const std::vector<VariantResult>& variants);

}  // namespace beadtwin::scenarios
