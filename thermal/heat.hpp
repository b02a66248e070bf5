// Transient heat transfer in the printed part, cell by cell on the thermal mesh (docs/physics.md, heat
// transfer in the part), and the fusion window of every interface.
//
// Each cell is a control volume of capacity ρ c_p V at one temperature. Cells exchange heat with the cells
// they touch through G = k_n A / d: A the contact's area, d the distance of the two centroids along its
// normal n, and k_n = nᵀ K n with K the orthotropic conductivity (along the bead, across it in plan,
// through the layer) averaged over the two cells' bead directions. Open surface loses heat by convection
// and radiation, h (T − T∞) + ε σ (T⁴ − T∞⁴), through the half cell under it (thermal/surface.hpp), the
// radiation weighted by what the surface sees of the sky and the table (thermal/view_factor.hpp); the
// surface on the table exchanges with it through the bed contact conductance (nothing on an insulated
// table). A cell is born at the deposition temperature when
// its material lands; until then it does not exist for its neighbours, whose faces towards it are open
// surface.
//
// Births come in groups: the cells laid within one birth interval are born together, at the middle of the
// group's birth times. The integration (SUNDIALS CVODE, BDF, GMRES preconditioned by the diagonal of the
// Newton matrix, the Jacobian applied exactly) restarts at every group. Energy lost through the boundary is
// integrated as one more state, so the balance in − lost − stored checks the bookkeeping.
//
// Every link marked as an interface is judged (thermal/fusion.hpp): the substrate temperature is the older
// cell's as the younger is born; the healing integral runs over the interface temperature (the mean of the
// two cells') from then until every interface has cooled below the material's healing threshold (at least
// to the end of the cooldown, at most to the end of the print + max_cooldown_s, where those still above it
// are reported), by two-point Gauss quadrature over each CVODE step on CVODE's own interpolant. The layers'
// history, the final temperatures and the energy balance end with the cooldown.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "core/material.hpp"
#include "thermal/communicator.hpp"
#include "thermal/fusion.hpp"
#include "thermal/mesh.hpp"

namespace beadtwin::thermal {

// The part-cooling fan's output (0 off, 1 full) from `time_s` on (Environment::fan_convection_W_m2K).
struct FanSetting {
  double time_s = 0.0;
  double output = 0.0;
};

// How solve_heat integrates: tolerances, births, lumping, the fan, what it records, progress and MPI ranks.
struct HeatOptions {
  double rel_tol = 1e-3;    // CVODE relative tolerance
  double abs_tol_k = 0.05;  // CVODE absolute tolerance on temperatures, K
  // Cells laid within this time are born together, s; 0: a fifth of the beads' median conduction time
  // constant (C / ΣG, a bead's slices through its height together, as they are once covered: lump), which
  // keeps the births' grouping well inside how fast a bead's temperature can move,
  // made longer where that would be more than max_automatic_birth_events: each event restarts the
  // integrator, and a long print of small beads (a desktop program) would be tens of thousands of them.
  double birth_interval_s = 0.0;
  std::size_t max_automatic_birth_events = 5000;
  double cooldown_s = 600.0;  // simulated after the end of the print (its last birth, or end_s), >= 0
  // Healing goes on after the cooldown while an interface is at or above the healing threshold, up to this
  // long after the end of the print, s (>= 0; the cooldown when shorter than it).
  double max_cooldown_s = 24.0 * 3600.0;
  // The fan's output over time, in time order (fan_schedule of a toolpath); empty: off throughout. A change
  // takes effect at the first birth group at or after it (within a birth interval), and during the cooldown
  // when it comes.
  std::vector<FanSetting> fan;
  SupportLoad support;  // the roller or tamper on a new bead (the too-hot verdict)
  // Further healing laws (each a material's reptation law: thermal/fusion.hpp Reptation) whose healing
  // integrals are followed beside the material's own over the same temperatures (HeatResult::law_integrals):
  // what the healing law's inputs do to healing costs no further heat solve.
  std::vector<Material> healing_laws;
  double sample_interval_s = 5.0;  // for the layers' temperature history, > 0
  int krylov_dimension = 10;
  // Settled cells lumped (docs/physics.md, settled cells): when at least lump_check_cells cells (and a
  // quarter of the model's) have been born since the last look, runs of consecutive born cells that touch
  // one another, lie more than lump_depth contacts below the top (cells with a neighbour not yet born) and
  // are within lump_tolerance_k of one another become one cell each, of at most 64 median beads' mass. A
  // long print's cells far below the top then cost each step a fraction of what they would unlumped. A bead
  // cut into n slices through its height (thermal.cells_through) becomes one cell, whatever the slices'
  // temperatures, once lump_slice_beads beads lie over it: once all its slices lie at least
  // lump_slice_beads × n contacts below the top (at most lump_depth). The slices resolve a bead's cooling
  // from its top while it is the top and the substrate of the next bead; below that the bead is one cell as
  // at one cell through, conducting from its own centroid (PartModel::lump).
  bool lump = true;
  int lump_depth = 20;
  int lump_slice_beads = 2;
  double lump_tolerance_k = 0.5;
  std::size_t lump_check_cells = 4096;
  double lump_max_cells = 64.0;  // a lumped cell's most mass, in median beads (a bead's slices together)
  // Each cell's surface for good radiates with its view factors of the sky and the table, found by rays
  // against the part as laid so far (thermal/view_factor.hpp; a mesh without its cell grid has none);
  // false: every open face sees only the sky.
  bool view_factors = true;
  // Times at which every cell's temperature is kept (thermal/snapshot_files.hpp), s; outside the simulated
  // span they are clamped to its ends.
  std::vector<double> snapshot_times_s;
  // Called on the calling thread at every birth, with the fraction of the simulated span done (0..1);
  // empty: no reports.
  std::function<void(double fraction)> progress;
  // Non-null (and more than one rank): the solve is shared among the ranks of an MPI job, each integrating
  // a slice of the part by height in SUNDIALS' MPI-parallel vectors. Every rank calls solve_heat with the
  // same mesh and options and gets the same whole result, which equals the one-rank solve within the
  // solver's tolerance (not to the last bit: the sums over the state are added in another order).
  Communicator* communicator = nullptr;
};

// Every cell's temperature at one moment, °C; NaN for cells not yet born.
struct TemperatureSnapshot {
  double time_s = 0.0;
  std::size_t request = 0;  // which of HeatOptions::snapshot_times_s asked for it
  std::vector<float> temp_c;
};

// One interface between two cells: what its substrate was as it formed, how far it healed, the verdict.
struct InterfaceResult {
  std::uint32_t older = 0, younger = 0;  // cells
  double area_mm2 = 0.0;
  bool on_top = false;  // the younger lands on the older (contact within 60° of horizontal)
  // The mean temperature of the older cell's bead through its height (its cells through the layer, by
  // volume) as the younger was born, °C.
  double substrate_c = 0.0;
  // The temperature of the older cell's face where the younger lands, as the younger was born, °C: the
  // surface a thermal camera reads just before the bead covers it (the cell's temperature less the drop
  // through its half cell, thermal/surface.hpp).
  double substrate_surface_c = 0.0;
  // How fast that bead was cooling then, K/s (NaN when both were born together).
  double substrate_rate_K_s = std::numeric_limits<double>::quiet_NaN();
  // The younger cell's temperature as it was born, °C (the deposition temperature, or the program's nozzle
  // temperature for its bead: ThermalCell::deposition_offset_k).
  double bead_c = std::numeric_limits<double>::quiet_NaN();
  // Where the younger lands on top (on_top): whether the soft material under it carries it
  // (thermal/support.hpp), with the temperatures as it landed.
  SupportResult support;
  double healing_integral = 0.0;  // ∫ dt / t_w over the interface's history, not capped at 1
  double healing = 0.0;           // min(1, D_h) = min(1, healing_integral^¼)
  // Still at or above the healing threshold when the healing integral ended (at the end of the print +
  // max_cooldown_s): its healing is what it had reached by then.
  bool still_warm = false;
  Verdict verdict = Verdict::kOk;
  // Over the plausible ranges of the inputs (thermal/uncertainty.hpp; NaN where not estimated): the P10 and
  // P90 of the substrate's and the surface's temperature as the younger was born (on_top only), °C, and of
  // the healing min(1, D_h).
  double substrate_p10_c = std::numeric_limits<double>::quiet_NaN();
  double substrate_p90_c = std::numeric_limits<double>::quiet_NaN();
  double surface_p10_c = std::numeric_limits<double>::quiet_NaN();
  double surface_p90_c = std::numeric_limits<double>::quiet_NaN();
  double healing_p10 = std::numeric_limits<double>::quiet_NaN();
  double healing_p90 = std::numeric_limits<double>::quiet_NaN();
  // The verdict at the cold end of the bands (P10 of the substrate's temperature and of the healing, each
  // against its threshold with the threshold's own spread) and at the hot end (P90); both the verdict where
  // not estimated.
  Verdict verdict_cold = Verdict::kOk, verdict_hot = Verdict::kOk;
  // The verdict changes within the bands: shown as marginal.
  bool marginal() const { return verdict_cold != verdict_hot; }
};

// What solve_heat found: every interface, the layers' history, snapshots, energy and the integrator's work.
struct HeatResult {
  std::vector<InterfaceResult> interfaces;  // one per interface link, in link order
  // [HeatOptions::healing_laws][interface]: ∫ dt / t_w under that law, as InterfaceResult::healing_integral.
  std::vector<std::vector<double>> law_integrals;
  double birth_interval_s = 0.0;      // the one used
  double automatic_interval_s = 0.0;  // a fifth of the median time constant (before any lengthening)
  std::vector<std::string> notes;     // what the solve chose for the user (a longer birth interval)
  std::size_t birth_events = 0;
  std::size_t view_updates = 0;        // cells' view factors found (thermal/view_factor.hpp)
  std::size_t view_rays = 0;           // rays cast for them
  std::size_t lump_events = 0;         // times settled cells were lumped
  std::size_t lumped_cells = 0;        // mesh cells in a lumped cell at the end
  std::size_t model_cells = 0;         // the model's cells at the end (the mesh's, less what lumping took)
  std::vector<double> sample_times_s;  // from the first birth to the end, every sample interval
  // [toolpath layer][sample]: volume-weighted mean temperature of the layer's born cells, °C; NaN before any.
  std::vector<std::vector<float>> layer_temp_c;
  std::vector<float> final_temp_c;             // per cell, at the end
  std::vector<TemperatureSnapshot> snapshots;  // at HeatOptions::snapshot_times_s, in time order
  // Energy relative to ambient, J: brought in by births, lost through the boundary (negative when the bed
  // heats the part), stored at the end; energy_balance_rel_error = |in − lost − stored| / max(|in|, |lost| +
  // |stored|).
  double energy_in_J = 0.0, energy_lost_J = 0.0, energy_stored_J = 0.0, energy_balance_rel_error = 0.0;
  long steps = 0, rhs_evaluations = 0, linear_iterations = 0;
  int ranks = 1;  // the MPI ranks the solve was shared among
  // From the first birth to the end of the cooldown (what the history, the final temperatures and the
  // energy balance cover), s.
  double start_time_s = 0.0, end_time_s = 0.0;
  // When the healing integral ended, s: every interface below the healing threshold, at end_time_s or
  // later; the interfaces still at or above it then (InterfaceResult::still_warm) and their area.
  double healing_end_s = 0.0;
  std::size_t still_warm = 0;
  double still_warm_area_mm2 = 0.0;
};

// The fan's changes over a timed toolpath: its output from each move on where it differs from the move
// before (the first setting at the first move's start when the fan is on there).
std::vector<FanSetting> fan_schedule(const Toolpath& toolpath);

// Solves the heat transfer on `mesh` from the first birth to the last birth + cooldown (at least to
// `end_s`, the end of the print, + cooldown), and on while interfaces heal (HeatOptions::max_cooldown_s).
// `layer_count`: how many toolpath layers there are (the cells' layer indices are below it). Throws
// InputError for options out of range, InternalError when the integrator fails. An empty mesh gives an empty
// result.
HeatResult solve_heat(const ThermalMesh& mesh, std::size_t layer_count, double end_s,
                      const Material& material, const Environment& env, const HeatOptions& options = {});

}  // namespace beadtwin::thermal
