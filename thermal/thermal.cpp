#include "thermal/thermal.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include <fmt/format.h>

namespace beadtwin::thermal {

namespace {

// The beads' temperature from the program's nozzle temperature (Move::nozzle_c), where it commands one:
// `material`'s deposition temperature becomes the one most of the print's volume is laid at (its range of
// plausible values moves with it: that range is the bead's spread about its set temperature), and each cell
// laid at another is born hotter or colder by the difference (ThermalCell::deposition_offset_k). Returns
// a note for the report; empty when the program commands no temperature.
std::string apply_nozzle_temperature(const Toolpath& tp, Material& material, ThermalMesh& mesh) {
  std::map<float, double> volume_at;  // °C -> mm³
  for (const Move& m : tp.moves)
    if (m.deposits() && std::isfinite(m.nozzle_c)) volume_at[m.nozzle_c] += m.volume_mm3;
  if (volume_at.empty()) return {};
  const auto most = std::max_element(volume_at.begin(), volume_at.end(),
                                     [](const auto& a, const auto& b) { return a.second < b.second; });
  const double base_c = most->first;
  const double shift_k = base_c - material.deposition_temp_c;
  for (InputRange& r : material.ranges)
    if (r.key == "deposition_temp" && !r.scale && r.spread != Spread::kNormal) {
      r.lo += shift_k;
      r.hi += shift_k;
    }
  const double file_c = material.deposition_temp_c;
  material.deposition_temp_c = base_c;
  for (ThermalCell& c : mesh.cells) {
    const float nozzle = c.move < tp.moves.size() ? tp.moves[c.move].nozzle_c : std::nanf("");
    c.deposition_offset_k = std::isfinite(nozzle) ? static_cast<double>(nozzle) - base_c : 0.0;
  }
  std::string note = fmt::format(
      "beads laid at the program's nozzle temperature (M104/M109): {:.0f} °C, {} the "
      "material file's deposition_temp{}",
      base_c, base_c == file_c ? "as" : "not", base_c == file_c ? "" : fmt::format(" of {:.0f} °C", file_c));
  if (volume_at.size() > 1)
    note += fmt::format("; {:.0f}-{:.0f} °C over the print, each bead at its own", volume_at.begin()->first,
                        volume_at.rbegin()->first);
  return note;
}

}  // namespace

ThermalResult solve_thermal(const ThermalInput& input) {
  const Toolpath& tp = input.toolpath;
  ThermalResult out;
  out.mesh = build_thermal_mesh(tp, input.deposit, input.mesh);
  Material material = input.material;
  const std::string nozzle_note = apply_nozzle_temperature(tp, material, out.mesh);
  HeatOptions heat = input.heat;
  if (heat.fan.empty() && input.environment.fan_convection_W_m2K > 0.0) heat.fan = fan_schedule(tp);
  UncertaintyPlan plan;
  if (input.uncertainty == UncertaintyMethod::kLinearised) {
    plan = plan_uncertainty(material, input.environment, !heat.fan.empty());
    plan.tolerance_factor = input.uncertainty_tolerance;
    heat.healing_laws = plan.law_materials();
  }
  out.heat = solve_heat(out.mesh, tp.layers.size(), tp.total_time_s(), material, input.environment, heat);
  if (input.uncertainty == UncertaintyMethod::kLinearised && !plan.inputs.empty()) {
    estimate_bands(plan, out.mesh, tp.layers.size(), tp.total_time_s(), material, heat, out.heat);
    out.uncertain_inputs = plan.inputs;
    out.extra_heat_solves = plan.heat.size();
    out.extra_healing_laws = plan.laws.size();
  }
  if (!nozzle_note.empty()) out.heat.notes.push_back(nozzle_note);
  std::vector<double> durations;
  for (const ToolpathLayer& l : tp.layers) durations.push_back(l.duration_s());
  out.layers = summarise_layers(out.mesh, out.heat, durations, material, input.environment.ambient_c);
  out.cells = cell_verdicts(out.mesh, out.heat);
  return out;
}

}  // namespace beadtwin::thermal
