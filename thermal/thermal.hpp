// The thermal stage (docs/physics.md, heat transfer in the part and fusion window): from a print's deposit to
// its thermal history and the fusion verdict of every interface between beads.
//
// The stage cuts the deposit's beads into control volumes (thermal/mesh.hpp), solves the heat transfer as
// they are born (thermal/heat.hpp), and sums up the interfaces per toolpath layer and per cell
// (thermal/summary.hpp). It reads the toolpath and the deposit and nothing of how they were made.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/material.hpp"
#include "core/toolpath.hpp"
#include "sim/deposit.hpp"
#include "thermal/fusion.hpp"
#include "thermal/heat.hpp"
#include "thermal/mesh.hpp"
#include "thermal/summary.hpp"
#include "thermal/uncertainty.hpp"

namespace beadtwin::thermal {

// What the thermal stage needs. The toolpath and the deposit are borrowed: they must outlive the call.
struct ThermalInput {
  const Toolpath& toolpath;     // the print, timed: its moves, layers and total time, s
  const sim::Deposit& deposit;  // made from `toolpath`, with its move and time grids
  Material material;
  Environment environment;
  MeshOptions mesh;  // how the beads are cut into cells
  // The integrator, births, lumping, the history and snapshot times (s, from the print's start), the
  // progress callback and the MPI ranks the solve is shared among.
  HeatOptions heat;
  // The P10-P90 bands of the interfaces over the ranges of material.ranges and environment.ranges
  // (thermal/uncertainty.hpp): off, or linearised at the cost of one more heat solve per heat input.
  UncertaintyMethod uncertainty = UncertaintyMethod::kOff;
  double uncertainty_tolerance = 1.0;  // the extra solves' tolerances as factors on heat's (> 0)
};

// What the thermal stage makes.
struct ThermalResult {
  ThermalMesh mesh;
  HeatResult heat;
  std::vector<FusionSummary> layers;  // parallel to Toolpath::layers
  std::vector<Verdict> cells;  // per thermal cell, its worst interface (cell_verdicts), for the fusion map
  // With the bands estimated: the inputs with a range that they use, the extra heat solves and healing
  // integrals they cost; empty and 0 without.
  std::vector<std::string> uncertain_inputs;
  std::size_t extra_heat_solves = 0, extra_healing_laws = 0;
};

// Builds the thermal mesh of `input.deposit`, solves its heat transfer from the first birth to the end of
// the print plus input.heat.cooldown_s, and sums up its interfaces per layer (with the layers' durations as
// printed) and per cell. Throws InputError for options out of range (naming the scenario's key),
// InternalError when the integrator fails. Across MPI ranks (input.heat.communicator) every rank calls it
// with the same input and gets the same result. A deposit without material gives an empty mesh and heat
// result.
ThermalResult solve_thermal(const ThermalInput& input);

}  // namespace beadtwin::thermal
