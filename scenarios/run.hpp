// The runner: the whole pipeline for every variant of a scenario, reading like the pipeline —
// part → slice → program → deposit → thermal → render → metrics and gates — then the reports.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "scenarios/input/result.hpp"
#include "sim/cad_compare.hpp"
#include "thermal/communicator.hpp"

namespace beadtwin::scenarios {

struct RunOptions {
  std::filesystem::path out_dir = "beadtwin-out";
  std::vector<std::string> variants;  // only these (all when empty); unknown names are an InputError
  std::function<void(const std::string&)> log;  // progress lines; empty to stay quiet
  // How far a run has got: the variant, the stage, and the stage's fraction done (0 as it starts, then
  // during the long stages, deposit and thermal); empty: no reports.
  std::function<void(const std::string& variant, const std::string& stage, double fraction)> progress;
  // Under mpirun: the ranks that share each variant's thermal solve (HeatOptions::communicator). This is rank
  // 0, which runs everything else and writes every output; the others call share_thermal. Null: alone.
  thermal::Communicator* thermal_ranks = nullptr;
};

// Runs the scenario and writes every output into options.out_dir. Throws InputError for bad input
// found late (for example an STL that cannot be read) before writing any report.
RunResult run_scenario(const Scenario& scenario, const RunOptions& options);

// A rank other than 0 of a run under mpirun (RunOptions::thermal_ranks): slices and deposits the variants as
// rank 0 does and takes its share of each thermal solve; writes nothing. Returns false when rank 0 stopped
// on bad input before any solve (it reports it).
bool share_thermal(const Scenario& scenario, const RunOptions& options);

// Slices one variant and returns its print program (for `beadtwin slice`).
std::string slice_program(const Scenario& scenario, const std::string& variant_name);

// The toolpath a variant prints: its program as written (timed with its machine), or its part sliced.
Toolpath variant_toolpath(const Variant& variant);

// The memory the rest of a run needs once its deposit is made, against the budget (docs/RELIABILITY.md). The
// estimate made before the deposit goes by the material's volume; a part that is mostly surface (a desktop
// print's thin infill walls) needs far more for what is meshed from it than a part of the same volume that
// is mostly solid. Once the deposit is made its surface is known. Estimated, each from what it grows with
// (measured, docs/RELIABILITY.md), so that the same input on the same machine gets the same answer:
//  - what the run holds: the moves with their motion plan, and the deposit's grids;
//  - the thermal stage: its cells (planned from the toolpath) and its grid of the cell each voxel is in;
//  - what is meshed from the surface (the pictures' surfaces and ray-tracing scenes, the skin, the
//    comparison's print surface): the faces of the deposit's voxels on its surface;
//  - a fixed allowance for the rest (the pictures' frames, the CAD's scene).
// Side by side the pictures' surfaces and scenes are held through the thermal stage; in turn they are built
// after it, and the peak is the larger of the two.
struct RunMemory {
  double program = 0.0;   // held: the moves with their motion plan, and the program's own, bytes
  double deposit = 0.0;   // held: the deposit's grids and what its work left to the allocator, bytes
  double cells = 0.0;     // the thermal cells, bytes
  double grids = 0.0;     // the grids later stages make on the deposit's voxels, bytes
  double surfaces = 0.0;  // what is meshed from the surface, bytes
  double budget = 0.0;    // output.memory_budget, or three quarters of the machine's memory
  // The run's peak, bytes, with the pictures' surfaces beside the thermal stage or after it.
  double side_by_side() const;
  double in_turn() const;
  // The same at voxels 1/r times as large: the grids go as the inverse cube of the voxel size, the surface
  // as its inverse square.
  RunMemory at_voxel_ratio(double r) const;
  // What the run needs at any voxel size: the program, the thermal cells and what every run holds, bytes.
  double least() const;
  // The smallest voxel size in tenths of a millimetre above `voxel_mm` (this estimate's) at which the run
  // fits in turn, with a tenth of the budget to spare; 0 when none would: the program and the thermal
  // cells alone take it.
  double fitting_voxel_mm(double voxel_mm) const;
};
RunMemory run_memory(const Variant& variant, const Toolpath& toolpath, const sim::Deposit& deposit);

// How the variant's machine and output settings deposit it: voxel size, what flattens the beads (the
// machine's kind), roller and nozzle, ooze, memory budget.
sim::DepositOptions deposit_options(const Variant& variant);

// The print against the variant's CAD, measured as a run measures it (its band and requested stock), or
// nothing when the variant has no CAD to compare with (a program read as written, an AM Outline section).
std::optional<sim::CadComparison> compare_variant_with_cad(const Variant& variant,
                                                           const sim::Deposit& deposit);

// `baseline`: the baseline variant's metrics, for the gates relative to it (null: such a gate fails, saying
// there is no baseline).
std::vector<GateResult> evaluate_gates(const std::vector<Gate>& gates, const Metrics& metrics,
                                       const Metrics* baseline = nullptr);
// The same over measured values (Metrics::values), as a sweep gathers them from its variants' reports.
std::vector<GateResult> evaluate_gates(const std::vector<Gate>& gates, const MetricValues& values,
                                       const MetricValues* baseline = nullptr);

// The variant the relative gates compare with: the one named "baseline", else the first.
std::size_t baseline_index(const std::vector<VariantResult>& variants);

}  // namespace beadtwin::scenarios
