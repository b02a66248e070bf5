// What each stage of a variant's run takes from the variant: the toolpath it prints, the options of the
// program writer, the deposit and the thermal stage, and the plan of its check against the CAD. The runner
// (run.cpp) calls each stage's entry function with these; the benchmarks and tests build the same inputs
// from the same functions, so they measure what a run does.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>

#include "core/toolpath.hpp"
#include "gcode/writer.hpp"
#include "scenarios/input/scenario.hpp"
#include "scenarios/variant_run.hpp"
#include "sim/cad_compare.hpp"
#include "sim/deposit.hpp"
#include "slicer/plan.hpp"
#include "thermal/communicator.hpp"
#include "thermal/thermal.hpp"

namespace beadtwin::scenarios {

// The toolpath the variant prints: its program as written, timed with its machine's motion, or its part
// sliced by its sections. `stats` (optional) receives what the planner found (passes laid, planned voids).
// Throws InputError when nothing would be printed (naming why: no section meets the part, or no bead fits).
Toolpath variant_toolpath(const Variant& variant, slicer::PlanStats* stats = nullptr);

// What the program writer needs of the sections (arc chord tolerance, melt settings) and of the extruder.
gcode::GcodeOptions gcode_options(const Variant& variant);

// How the variant's machine and output settings deposit it: voxel size, what flattens the beads (the
// machine's kind), roller and nozzle, ooze, memory budget.
sim::DepositOptions deposit_options(const Variant& variant);

// Deposits the variant's toolpath `toolpath`, at `voxel_size_mm` when positive (else the variant's).
// `progress` hears the fraction done (may be empty). An error in the voxel size names output.voxel_size.
sim::Deposit deposit_variant(const Variant& variant, const Toolpath& toolpath,
                             std::function<void(double)> progress, double voxel_size_mm = 0.0);

// How the variant's thermal settings cut its beads into cells.
thermal::MeshOptions thermal_mesh_options(const Variant& variant);

// What the thermal stage needs of the variant printing `toolpath` into `deposit`: its thermal settings,
// material and environment; the scenario's snapshots first (written as files), then the moments the
// pictures colour by temperature. `progress` may be empty; `ranks` is null when solving alone.
thermal::ThermalInput thermal_input(const Variant& variant, const Toolpath& toolpath,
                                    const sim::Deposit& deposit, std::function<void(double)> progress,
                                    thermal::Communicator* ranks);

// The CAD a variant's print is compared with, and how, on voxels of a given size.
struct CadPlan {
  slicer::TriangleMesh cad;
  sim::CadCompareOptions options;
  double requested_stock_mm = 0.0, map_half_range_mm = 0.0;
  sim::CadSurface surface() const { return {cad.vertices, cad.triangles}; }
};
// The plan on voxels of `voxel_mm` (mm); nothing when the variant has no CAD to compare with (a program
// simulated, or sections that print outlines). The band reaches the requested stock and a bead width
// beyond it (stocks beyond that are reported as "at least"), within 4..32 voxels.
std::optional<CadPlan> plan_cad_check(const Variant& variant, double voxel_mm);

// The part of the CAD check that needs no deposit, made while the deposit runs: the plan and the CAD's
// distance grid on the voxels the deposit will use (voxel_mm).
struct CadAhead {
  double voxel_mm = 0.0;
  CadPlan plan;
  sim::CadDistance distance;
};
std::optional<CadAhead> cad_check_ahead(const Variant& variant, const Toolpath& toolpath);

// The print against its CAD, with what was made ahead when it is on the deposit's voxels (else all of it
// here); nothing when the variant has no CAD to compare with.
std::optional<CadCheck> check_against_cad(const Variant& variant, const sim::Deposit& deposit,
                                          const std::optional<CadAhead>& ahead);

// The same, as the comparison alone: the print against the variant's CAD, measured as a run measures it.
std::optional<sim::CadComparison> compare_variant_with_cad(const Variant& variant,
                                                           const sim::Deposit& deposit);

}  // namespace beadtwin::scenarios
