#include "thermal/thermal.hpp"

namespace beadtwin::thermal {

ThermalResult solve_thermal(const ThermalInput& input) {
  const Toolpath& tp = input.toolpath;
  ThermalResult out;
  out.mesh = build_thermal_mesh(tp, input.deposit, input.mesh);
  HeatOptions heat = input.heat;
  if (heat.fan.empty() && input.environment.fan_convection_W_m2K > 0.0) heat.fan = fan_schedule(tp);
  UncertaintyPlan plan;
  if (input.uncertainty == UncertaintyMethod::kLinearised) {
    plan = plan_uncertainty(input.material, input.environment, !heat.fan.empty());
    plan.tolerance_factor = input.uncertainty_tolerance;
    heat.healing_laws = plan.law_materials();
  }
  out.heat =
      solve_heat(out.mesh, tp.layers.size(), tp.total_time_s(), input.material, input.environment, heat);
  if (input.uncertainty == UncertaintyMethod::kLinearised && !plan.inputs.empty()) {
    estimate_bands(plan, out.mesh, tp.layers.size(), tp.total_time_s(), input.material, heat, out.heat);
    out.uncertain_inputs = plan.inputs;
    out.extra_heat_solves = plan.heat.size();
    out.extra_healing_laws = plan.laws.size();
  }
  std::vector<double> durations;
  for (const ToolpathLayer& l : tp.layers) durations.push_back(l.duration_s());
  out.layers = summarise_layers(out.mesh, out.heat, durations, input.material, input.environment.ambient_c);
  out.cells = cell_verdicts(out.mesh, out.heat);
  return out;
}

}  // namespace beadtwin::thermal
