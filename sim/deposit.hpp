// Voxel deposition (docs/physics.md, bead cross-section and deposition), first cut.
//
// Every print move sweeps its flattened bead cross-section — a rectangle with semicircular sides, height h
// = the move's layer height, width w from A = Q/v = h (w - h) + π h²/4 — into sparse OpenVDB grids in the
// machine frame. The bead's top is the move's z; its bottom is z - h. Material is conserved: each move
// puts exactly its commanded volume into the grid, and material that meets a full voxel is pushed on into
// free neighbouring space rather than lost.
//
// How the pieces fit (one file pair each): sim/bead_section (the profile of a bead or a puddle),
// sim/sweep_plan (moves to sweeps: which moves continue one bead, how the ends are cut), sim/bead_sweep
// (the swept solid and its supersampled voxel coverage), sim/fill_writer (conservation: scaling, overflow
// pushed to free neighbours), sim/porosity (void inside the envelope). This file is the stage.
//
// Conventions the consumers (thermal, render, reports) rely on:
//  - Voxel (i,j,k) spans [i, i+1) · voxel_size_mm along x (likewise y, z), in mm, machine frame. The grids'
//    transform is deposit_transform(voxel_size_mm): it maps index (i,j,k) to the voxel's centre
//    ((i+½)·s, (j+½)·s, (k+½)·s), as OpenVDB expects (a value sits at the centre of its voxel), so
//    grid->transform().worldToIndexCellCentered(p) and voxel_containing(p, s) name the same voxel.
//  - fill, time and layer share one active topology: a voxel is active iff it holds material (fill > 0).
//    Inactive voxels read the backgrounds: fill 0, time 0, layer -1.
//  - Every move with volume_mm3 > 0 deposits, whatever its kind; a move without plan length (a dwell that
//    extrudes) leaves a puddle at its end point (sim/sweep_plan.hpp).
#pragma once

#include <openvdb/openvdb.h>
#include <Eigen/Core>

#include "core/toolpath.hpp"

namespace beadtwin::sim {

// The flattened bead's section is core/bead.hpp's stadium. A bead of area below π h²/4 cannot reach the
// roller; the deposit lays it as a round bead of that area whose top is at the roller (sim/bead_section.hpp).

struct DepositOptions {
  double voxel_size_mm = 0.0;  // 0: chosen from the beads (half the smallest layer height)
  int supersample = 3;  // samples per voxel edge when measuring how much of a voxel a bead covers, 1..16
                        // (in plan; the height a bead covers above each sample is exact)
  // Ends of a bead that do not join another move (path start and stop): false cuts them square at the
  // commanded point, so a straight bead holds exactly A·L; true rounds them in plan (the nozzle's round
  // footprint), which lengthens the bead by its width and so spreads the same material a little thinner.
  // Corners between joined moves are always the swept footprint: round outside, mitred inside.
  bool round_free_ends = false;
};

struct Deposit {
  double voxel_size_mm = 0.0;
  // Fill fraction per voxel, 0..1. Index space: voxel (i,j,k) spans [i,i+1)*voxel_size_mm etc.
  openvdb::FloatGrid::Ptr fill;
  // Time (s) the voxel last received material.
  openvdb::FloatGrid::Ptr time;
  // Toolpath layer index of the material in the voxel (-1 background, and for moves without a layer).
  openvdb::Int32Grid::Ptr layer;

  double commanded_volume_mm3 = 0.0;      // sum of the toolpath's move volumes
  double deposited_volume_mm3 = 0.0;      // sum of fill fractions times the voxel volume
  double swept_volume_mm3 = 0.0;          // geometric volume of the swept bead shapes before conservation
  double redistributed_volume_mm3 = 0.0;  // material pushed out of full voxels into free neighbours
  double porosity = 0.0;                  // void fraction inside the printed envelope
  double void_volume_mm3 = 0.0;           // empty volume inside the printed envelope (sim/porosity.hpp)
  std::size_t active_voxels = 0;
};

// Deposits every print move of `toolpath`. Throws InputError for a toolpath that cannot be deposited
// (for example a non-positive layer height on a print move), naming the move.
// Deterministic: the grids and numbers do not depend on the number of threads.
Deposit deposit(const Toolpath& toolpath, const DepositOptions& options = {});

// The grids' transform for voxels of `voxel_size_mm` (> 0): index (i,j,k) ↦ centre ((i+½)s, (j+½)s, (k+½)s).
openvdb::math::Transform::Ptr deposit_transform(double voxel_size_mm);
// The voxel that contains `point_mm` (machine frame).
openvdb::Coord voxel_containing(const Eigen::Vector3d& point_mm, double voxel_size_mm);
// The centre of voxel `ijk`, mm.
Eigen::Vector3d voxel_center_mm(const openvdb::Coord& ijk, double voxel_size_mm);

}  // namespace beadtwin::sim
