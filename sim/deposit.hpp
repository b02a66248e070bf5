// Voxel deposition (docs/physics.md, bead cross-section and deposition).
//
// Every print move sweeps its flattened bead cross-section — a rectangle with semicircular sides, height h
// = the move's layer height, width w from A = Q/v = h (w - h) + π h²/4 — into sparse OpenVDB grids in the
// machine frame. The bead's top is the move's z; its bottom is z - h. Material is conserved: each move
// puts exactly its commanded volume into the grid, and material that meets a full voxel is pushed on into
// free neighbouring space rather than lost.
//
// How the pieces fit (one file pair each): sim/bead_section (the profile of a bead or a puddle),
// sim/sweep_plan (moves to sweeps: which moves continue one bead, how the ends are cut), sim/bead_sweep
// (the swept solid and its supersampled voxel coverage), sim/substrate (what lies under a bead),
// sim/fill_writer (conservation: scaling, overflow pushed to free neighbours), sim/porosity (void inside the
// envelope), sim/voids (the voids located), sim/defects (what is wrong, where, and the check of the roller's
// corners), sim/travel_collision (travel moves that run into the part). This file is the stage.
//
// Conventions the consumers (thermal, render, reports) rely on:
//  - Voxel (i,j,k) spans [i, i+1) · voxel_size_mm along x (likewise y, z), in mm, machine frame. The grids'
//    transform is deposit_transform(voxel_size_mm): it maps index (i,j,k) to the voxel's centre
//    ((i+½)·s, (j+½)·s, (k+½)·s), as OpenVDB expects (a value sits at the centre of its voxel), so
//    grid->transform().worldToIndexCellCentered(p) and voxel_containing(p, s) name the same voxel.
//  - fill, time, layer and move share one active topology: a voxel is active iff it holds material
//    (fill > 0). Inactive voxels read the backgrounds: fill 0, time 0, layer -1, move -1.
//  - Every move with volume_mm3 > 0 deposits, whatever its kind; a move without plan length (a dwell that
//    extrudes) leaves a puddle at its end point (sim/sweep_plan.hpp).
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include <openvdb/openvdb.h>
#include <Eigen/Core>

#include "core/memory.hpp"
#include "core/toolpath.hpp"
#include "sim/defects.hpp"

namespace beadtwin::sim {

// The flattened bead's section is core/bead.hpp's stadium. A bead of area below π h²/4 cannot reach the
// roller; the deposit lays it as a round bead of that area whose top is at the roller (sim/bead_section.hpp).

// What flattens a bead to the layer height.
enum class Flattening : std::uint8_t {
  kNozzle,  // the nozzle's tip (desktop FFF, robot cells): every bead is flattened
  kRoller,  // a compression roller following the nozzle: flattened where Move::roller_down, round elsewhere
  kTamper,  // a tamping foot (BAAM class): likewise, by Move::roller_down (the tamper running)
};
std::string_view to_string(Flattening flattening);

// How deposit() lays the beads into voxels.
struct DepositOptions {
  double voxel_size_mm = 0.0;  // 0: chosen from the beads (half the smallest layer height, coarser when that
                               // would not fit the memory budget)
  int supersample = 3;  // samples per voxel edge when measuring how much of a voxel a bead covers, 1..16
                        // (in plan; the height a bead covers above each sample is exact)
  // Ends of a bead that do not join another move (path start and stop): false cuts them square at the
  // commanded point, so a straight bead holds exactly A·L; true rounds them in plan (the nozzle's round
  // footprint), which lengthens the bead by its width and so spreads the same material a little thinner.
  // Corners between joined moves are always the swept footprint: round outside, mitred inside.
  bool round_free_ends = false;

  Flattening flattening = Flattening::kNozzle;
  // The bead's bottom follows the material really below it (sim/substrate.hpp): false lays every bead at
  // its nominal layer height, whatever is under it.
  bool follow_substrate = true;
  // Longest piece a move is cut into for following the substrate, in bead widths (> 0).
  double piece_bead_widths = 2.0;
  double roller_width_mm = 0.0;     // 0: unknown (no corner check); the roller's width across the bead
  double roller_diameter_mm = 0.0;  // 0: unknown; the roller meets material up to its radius above a bead
  double nozzle_diameter_mm = 0.0;  // 0: unknown; the nozzle's tip, for collisions on travel moves
  // Ooze: the time constant of the nozzle's pressure decay after a melt off, s (sim/sweep_plan.hpp); 0: none.
  double ooze_time_s = 0.0;
  // The build table's height, mm; NaN: the lowest nominal bead bottom of the toolpath.
  double table_z_mm = std::numeric_limits<double>::quiet_NaN();
  // Memory the run may use, bytes; 0: three quarters of the machine's physical memory. The estimate counts
  // the deposit's grids (deposit_cost) and what the stages after it build from them while they are held;
  // above it the run stops before any voxel is written, with a voxel size that would fit, or an automatic
  // voxel size is made coarser.
  double memory_budget_bytes = 0.0;
  // What the stages after the deposit build from it while it is held, bytes per byte of its grids: the
  // caller's stages, not the deposit's (the scenario runner supplies its own, scenarios/run_memory.hpp). The
  // default is the runner's, so that the deposit used alone (benchmarks, tests) checks as within a run; 0
  // counts the deposit alone.
  double later_bytes_per_deposit_byte = 2.5;
  // Called on the calling thread as the layers are laid, with the fraction of the beads laid so far (0..1);
  // empty: no reports.
  std::function<void(double fraction)> progress;
};

// Per toolpath layer: the material it was commanded and what the deposit made of it.
struct LayerDeposit {
  double commanded_volume_mm3 = 0.0;
  // Commanded over nominal: the layer's outline area times its height (ToolpathLayer::outline_area_mm2); 0
  // when the toolpath does not know the outline. Below 1 the layer is under-filled, above it over-filled.
  double fill_ratio = 0.0;
  double mean_bead_height_mm = 0.0;  // the beads' height after following the substrate, length-weighted
  double void_volume_mm3 = 0.0;      // enclosed voids next to the layer's beads
  double plough_volume_mm3 = 0.0;    // material pushed above the roller while laying the layer
  double unsupported_length_mm = 0.0;
};

// The printed part as voxels: the grids deposit() fills, what became of the material, and its defects.
struct Deposit {
  double voxel_size_mm = 0.0;
  // Fill fraction per voxel, 0..1. Index space: voxel (i,j,k) spans [i,i+1)*voxel_size_mm etc.
  openvdb::FloatGrid::Ptr fill;
  // The grids below name, per voxel, the move that brought it at least as much material as it already held
  // (sim/fill_writer.hpp): the move whose material it mostly is, not one that later topped it up.
  // Time (s) that material landed.
  openvdb::FloatGrid::Ptr time;
  // Its toolpath layer index (-1 background, and for moves without a layer).
  openvdb::Int32Grid::Ptr layer;
  // Its move: index into Toolpath::moves (-1 background).
  openvdb::Int32Grid::Ptr move;
  // The enclosed gaps between beads (sim/porosity.hpp): empty voxels inside the part, whose walls do not
  // see the outside air.
  openvdb::MaskGrid::Ptr gaps;

  double commanded_volume_mm3 = 0.0;      // sum of the toolpath's move volumes
  double deposited_volume_mm3 = 0.0;      // sum of fill fractions times the voxel volume
  double swept_volume_mm3 = 0.0;          // geometric volume of the swept bead shapes before conservation
  double redistributed_volume_mm3 = 0.0;  // material pushed out of full voxels into free neighbours
  double porosity = 0.0;                  // void fraction inside the printed envelope
  double void_volume_mm3 = 0.0;           // empty volume inside the printed envelope (sim/porosity.hpp)
  std::size_t active_voxels = 0;
  std::size_t surface_faces = 0;  // voxel faces on the part's surface (sim/porosity.hpp)

  std::vector<Defect> defects;       // in toolpath order; voids last
  std::vector<LayerDeposit> layers;  // parallel to Toolpath::layers
  double plough_volume_mm3 = 0.0;
  double unsupported_length_mm = 0.0;
  double ooze_volume_mm3 = 0.0;  // laid after melt offs (on dwells and travels), part of the commanded volume
  double memory_estimate_bytes = 0.0;  // what the run was estimated to need before the deposit started
  std::vector<std::string> notes;      // what the deposit chose for the user (a coarser voxel, ...)
  std::size_t void_count = 0;  // voids of at least a voxel's volume (the largest are listed in defects)
};

// Deposits every print move of `toolpath`. Throws InputError for a toolpath that cannot be deposited
// (for example a non-positive layer height on a print move), naming the move.
// Deterministic: the grids and numbers do not depend on the number of threads.
Deposit deposit(const Toolpath& toolpath, const DepositOptions& options = {});

// The voxel size deposit() would use for `toolpath` with `options`, mm, known before it runs (what is made
// on the deposit's voxels can start beside it). Throws InputError as deposit() does for a toolpath that
// cannot be deposited or a voxel size that does not fit the memory budget.
double deposit_voxel_size_mm(const Toolpath& toolpath, const DepositOptions& options = {});

// What the deposit of `toolpath` at `voxel_size_mm` will hold, bytes, estimated before any voxel is written
// from the material the toolpath commands: its grids, all of it going as the inverse cube of the voxel size.
MemoryCost deposit_cost(const Toolpath& toolpath, double voxel_size_mm);
// What a made deposit holds while the stages after it run, bytes: its grids and what its work left to the
// allocator (volume bytes at its voxel size).
MemoryCost deposit_cost(const Deposit& deposit);
// What the stages after the deposit mesh from its surface (the pictures' surfaces and ray-tracing scenes,
// the skin, the CAD comparison's print surface), bytes: per voxel face on its surface (surface bytes at its
// voxel size).
MemoryCost surface_cost(const Deposit& deposit);

// The grids' transform for voxels of `voxel_size_mm` (> 0): index (i,j,k) ↦ centre ((i+½)s, (j+½)s, (k+½)s).
openvdb::math::Transform::Ptr deposit_transform(double voxel_size_mm);
// The voxel that contains `point_mm` (machine frame).
openvdb::Coord voxel_containing(const Eigen::Vector3d& point_mm, double voxel_size_mm);
// The centre of voxel `ijk`, mm.
Eigen::Vector3d voxel_center_mm(const openvdb::Coord& ijk, double voxel_size_mm);
// The lowest voxel index k whose voxels' centres lie at or above `z_mm` (the first row above a roller at
// that height).
int voxel_row_at_or_above(double z_mm, double voxel_size_mm);

// The fill of the part as it stood when toolpath layer `last_layer` was done: the voxels whose material
// came from layers 0..last_layer (the layer grid names the layer whose material a voxel mostly is, so a
// voxel is in or out whole: in with the layer that brought most of it, even if a later layer topped it up).
// Same transform as the deposit's fill. Preconditions: the deposit has fill and layer grids.
openvdb::FloatGrid::Ptr fill_up_to_layer(const Deposit& deposit, int last_layer);
// The fill of the part as it stood at `time_s` (s from the start of the print): the voxels whose material
// had landed by then (the time grid names when the material a voxel mostly is landed). Preconditions: the
// deposit has fill and time grids.
openvdb::FloatGrid::Ptr fill_up_to_time(const Deposit& deposit, double time_s);

}  // namespace beadtwin::sim
