#include "scenarios/variant_stages.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"
#include "scenarios/pictures.hpp"
#include "scenarios/run_memory.hpp"
#include "slicer/mesh.hpp"

namespace beadtwin::scenarios {

Toolpath variant_toolpath(const Variant& v, slicer::PlanStats* stats) {
  if (v.program) {
    // A program read as it was written: timed with this machine's motion.
    Toolpath tp = *v.program;
    if (tp.layers.empty())
      throw InputError({v.program_file.string(), 0, 0}, "program",
                       "the program deposits no material: there is nothing to simulate");
    if (std::none_of(tp.moves.begin(), tp.moves.end(), [](const Move& m) { return m.deposits(); }))
      throw InputError({v.program_file.string(), 0, 0}, "program",
                       fmt::format("the program's print moves carry no material on machine '{}': the reader "
                                   "found no flow for them (the warnings above say why); name the machine "
                                   "that prints it (--machine, or the scenario's machine), whose extruder "
                                   "gives the flow from a pump's speed words or a filament drive's constant "
                                   "feed",
                                   v.machine.name));
    time_toolpath(tp, v.machine.motion);
    return tp;
  }
  BT_CHECK(v.part.loaded != nullptr);
  Toolpath tp =
      slicer::plan_toolpath(*v.part.loaded, v.sections, v.machine.motion, stats, &v.machine.extruder);
  if (tp.layers.empty())
    throw InputError({}, "sections",
                     fmt::format("variant '{}': no section's Z range meets the part ({}), nothing to print",
                                 v.name, v.part.describe()));
  if (std::none_of(tp.moves.begin(), tp.moves.end(), [](const Move& m) { return m.deposits(); })) {
    // Layers, but no bead fits in any of them: the beads are wider than the part's sections.
    double widest = 0;
    for (const auto& s : v.sections) widest = std::max(widest, s.bead_width_mm);
    const Eigen::Vector3d size = v.part.loaded->max_corner() - v.part.loaded->min_corner();
    throw InputError(
        {}, "sections",
        fmt::format("variant '{}': no bead fits in any layer, nothing to print: the beads (up to "
                    "{:.4g} mm wide) are wider than the part's sections ({:.4g} x {:.4g} mm at "
                    "most); choose a narrower bead_width",
                    v.name, widest, size.x(), size.y()));
  }
  return tp;
}

gcode::GcodeOptions gcode_options(const Variant& v) {
  gcode::GcodeOptions o;
  for (const auto& s : v.sections) {
    o.arc_tolerance_mm.push_back(s.arc_chord_tolerance_mm);
    o.melt.push_back(s.melt);
  }
  // Speed words need the pump's displacement; E words the filament's diameter.
  if (v.machine.extruder.has_commands()) o.extruder = &v.machine.extruder;
  return o;
}

thermal::MeshOptions thermal_mesh_options(const Variant& v) {
  thermal::MeshOptions o;
  o.cells_across = v.thermal.cells_across;
  o.cells_through = v.thermal.cells_through;
  o.cell_length_mm = v.thermal.cell_length_mm;
  return o;
}

thermal::ThermalInput thermal_input(const Variant& v, const Toolpath& tp, const sim::Deposit& deposit,
                                    std::function<void(double)> progress, thermal::Communicator* ranks) {
  thermal::HeatOptions ho;
  ho.rel_tol = v.thermal.rel_tol;
  ho.abs_tol_k = v.thermal.abs_tol_k;
  ho.lump = v.thermal.lump;
  ho.view_factors = v.thermal.view_factors;
  ho.birth_interval_s = v.thermal.birth_interval_s;
  ho.cooldown_s = v.thermal.cooldown_s;
  ho.max_cooldown_s = v.thermal.max_cooldown_s;
  ho.sample_interval_s = v.thermal.sample_interval_s;
  ho.support = {.roller_pressure_Pa = v.machine.roller_pressure_Pa,
                .roller_contact_mm = v.machine.roller_contact_mm};
  for (const double t : v.thermal.snapshot_times_s)
    ho.snapshot_times_s.push_back(std::isinf(t) ? tp.total_time_s() : t);
  for (const double t : picture_snapshot_times(v.render, tp)) ho.snapshot_times_s.push_back(t);
  ho.progress = std::move(progress);
  ho.communicator = ranks;
  return {.toolpath = tp,
          .deposit = deposit,
          .material = v.material,
          .environment = v.machine.environment,
          .mesh = thermal_mesh_options(v),
          .heat = std::move(ho),
          .uncertainty = v.thermal.uncertainty,
          .uncertainty_tolerance = v.thermal.uncertainty_tolerance};
}

sim::Deposit deposit_variant(const Variant& v, const Toolpath& tp, std::function<void(double)> progress,
                             double voxel_size_mm) {
  try {
    sim::DepositOptions o = deposit_options(v);
    if (voxel_size_mm > 0.0) o.voxel_size_mm = voxel_size_mm;
    o.progress = std::move(progress);
    return sim::deposit(tp, o);
  } catch (const InputError& e) {
    // The deposit knows the option, not where it was written: name the scenario's key.
    if (e.key() != "voxel_size") throw;
    throw InputError(v.output.voxel_size_at, "output.voxel_size", e.message());
  }
}

std::optional<CadPlan> plan_cad_check(const Variant& v, double voxel_mm) {
  if (v.program || !v.part.loaded) return std::nullopt;
  std::optional<slicer::TriangleMesh> cad = slicer::printed_cad(*v.part.loaded, v.sections);
  if (!cad) return std::nullopt;
  const StockScale stock = stock_scale(v);
  CadPlan plan;
  plan.cad = std::move(*cad);
  plan.requested_stock_mm = stock.requested_mm;
  plan.map_half_range_mm = stock.half_range_mm;
  plan.options.requested_stock_mm = stock.requested_mm;
  plan.options.band_mm =
      std::clamp(std::abs(stock.requested_mm) + stock.widest_bead_mm, 4.0 * voxel_mm, 32.0 * voxel_mm);
  return plan;
}

std::optional<CadAhead> cad_check_ahead(const Variant& v, const Toolpath& tp) {
  if (v.program || !v.part.loaded) return std::nullopt;
  CadAhead ahead;
  try {
    ahead.voxel_mm = sim::deposit_voxel_size_mm(tp, deposit_options(v));
  } catch (const InputError&) {
    return std::nullopt;  // the deposit says what is wrong, naming the scenario's key
  }
  std::optional<CadPlan> plan = plan_cad_check(v, ahead.voxel_mm);
  if (!plan) return std::nullopt;
  ahead.plan = std::move(*plan);
  ahead.distance = sim::cad_distance(ahead.plan.surface(), ahead.voxel_mm, ahead.plan.options);
  return ahead;
}

std::optional<CadCheck> check_against_cad(const Variant& v, const sim::Deposit& deposit,
                                          const std::optional<CadAhead>& ahead) {
  const bool usable = ahead && ahead->voxel_mm == deposit.voxel_size_mm;
  std::optional<CadPlan> fresh;
  if (!usable) fresh = plan_cad_check(v, deposit.voxel_size_mm);
  const CadPlan* plan = usable ? &ahead->plan : fresh ? &*fresh : nullptr;
  if (plan == nullptr) return std::nullopt;
  CadCheck check;
  check.requested_stock_mm = plan->requested_stock_mm;
  check.map_half_range_mm = plan->map_half_range_mm;
  check.comparison =
      sim::compare_with_cad(deposit, plan->surface(), plan->options, usable ? &ahead->distance : nullptr);
  return check;
}

sim::DepositOptions deposit_options(const Variant& v) {
  sim::DepositOptions o;
  o.voxel_size_mm = v.output.voxel_size_mm;
  o.flattening = v.machine.kind == MachineKind::kRollerGantry   ? sim::Flattening::kRoller
                 : v.machine.kind == MachineKind::kTamperGantry ? sim::Flattening::kTamper
                                                                : sim::Flattening::kNozzle;
  o.roller_width_mm = v.machine.roller_width_mm;
  o.roller_diameter_mm = v.machine.roller_diameter_mm;
  o.nozzle_diameter_mm = v.machine.nozzle_diameter_mm;
  o.ooze_time_s = v.machine.ooze_time_s;
  o.memory_budget_bytes = v.output.memory_budget_gb * 1e9;
  o.later_bytes_per_deposit_byte = later_bytes_per_deposit_byte();
  return o;
}

std::optional<sim::CadComparison> compare_variant_with_cad(const Variant& variant,
                                                           const sim::Deposit& deposit) {
  std::optional<CadCheck> check = check_against_cad(variant, deposit, std::nullopt);
  if (!check) return std::nullopt;
  return std::move(check->comparison);
}

}  // namespace beadtwin::scenarios
