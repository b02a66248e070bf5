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
#include <vector>

#include "core/toolpath.hpp"
#include "sim/bead_sweep.hpp"

namespace beadtwin::sim {

struct PlannedSweep {
  std::size_t move = 0;  // index into Toolpath::moves
  BeadSweep sweep;
};

// Precondition: the toolpath's depositing moves have finite coordinates and positive layer heights.
std::vector<PlannedSweep> plan_sweeps(const Toolpath& toolpath, bool round_free_ends);

}  // namespace beadtwin::sim
