// From a toolpath's depositing moves to bead sweeps (docs/physics.md, deposition): each move's bead
// cross-section and how its ends meet its neighbours.
//
// Consecutive depositing moves form one continuous bead when the first ends where the second starts
// (within 1 µm), only moves without length (events, dry dwells) lie between them, and the path turns by
// less than 170°; a bead that ends where it started closes on itself the same way. Where two moves join,
// both are cut on the corner's bisector plane (see sim/bead_sweep.hpp). Sharper reversals are left as two
// free ends whose overlap the conservation step resolves.
//
// Any move with volume > 0 deposits, whatever its kind: the commanded volume is what the deposit must
// hold. A moving bead has area A = volume / length (3-D length, as the flow is Q/v along the move); a move
// without plan length (a dwell that extrudes, a print move that does not move, a vertical move) leaves a
// puddle at its end point.
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "core/toolpath.hpp"
#include "sim/bead_sweep.hpp"

namespace beadtwin::sim {

// One piece of a depositing move: a move longer than the piece length is cut into equal pieces, so the
// deposit can follow the substrate under it (sim/substrate.hpp) piece by piece.
struct PlannedSweep {
  std::size_t move = 0;  // index into Toolpath::moves
  BeadSweep sweep;       // with the nominal profile: flattened to the move's layer height
  double along_start = 0.0, along_end = 1.0;  // the piece's part of its move, 0 (start) .. 1 (end)
  double volume_mm3 = 0.0;                    // the material the piece lays: its share of the move's
  // The nominal top and bottom of the bead (the roller's height, the move's z, and that less the layer
  // height), at the piece's middle.
  double nominal_top_mm = 0.0;
  double nominal_height_mm = 0.0;
  bool ooze = false;  // material oozing from the nozzle after a melt off (see plan_sweeps)
};

// How plan_sweeps cuts and shapes the moves.
struct SweepPlanOptions {
  bool round_free_ends = false;  // see DepositOptions::round_free_ends
  // Longest piece, mm (> 0): moves are cut into equal pieces no longer than this. Infinity keeps every move
  // whole.
  double max_piece_mm = std::numeric_limits<double>::infinity();
  // Ooze (DepositOptions::ooze_time_s): the time constant of the nozzle's pressure after a melt off, s; 0
  // for none.
  double ooze_time_s = 0.0;
};

// Ooze: after a melt off that neither a coast nor a reverse follows, the melt still under pressure in the
// nozzle flows on, its flow falling from the bead's Q0 as Q0·exp(−t/τ). Over the dwells and travels that
// follow (until material is laid or the melt turns on, reverses or primes again) each gets
// Q0·τ·(exp(−t0/τ) − exp(−t1/τ)): a puddle on a dwell, a thin string along a travel. The pump delivered
// that material with the bead, so it is taken from the bead's last piece (at most half of it), and the
// total stays the commanded volume. Such pieces have PlannedSweep::ooze set.
//
// Precondition: the toolpath's depositing moves have finite coordinates and positive layer heights.
std::vector<PlannedSweep> plan_sweeps(const Toolpath& toolpath, const SweepPlanOptions& options);

}  // namespace beadtwin::sim
