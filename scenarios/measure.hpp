// What a variant's run measured, from what its stages made: the part's metrics (scenarios/input/metrics.hpp
// declares them), each layer's and each section's figures, the layers' temperature against time and the
// deposit's defects, as the reports show them.
#pragma once

#include <optional>

#include "core/toolpath.hpp"
#include "scenarios/input/result.hpp"
#include "scenarios/variant_run.hpp"
#include "sim/deposit.hpp"
#include "slicer/plan.hpp"
#include "thermal/thermal.hpp"

namespace beadtwin::scenarios {

// Fills `result`'s metrics, layers, temperature history and defects for `variant` printing `toolpath`
// (planned with `plan`: passes laid, voids found) into `deposit`, cooled as `thermal` found, compared with
// its CAD as `cad` found (nothing without a CAD).
void measure_variant(const Variant& variant, const Toolpath& toolpath, const slicer::PlanStats& plan,
                     const sim::Deposit& deposit, const thermal::ThermalResult& thermal,
                     const std::optional<CadCheck>& cad, VariantResult& result);

}  // namespace beadtwin::scenarios
