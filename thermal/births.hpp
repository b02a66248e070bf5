// The birth schedule of the heat solve, internal to the thermal library (thermal/heat.hpp, HeatOptions'
// birth_interval_s): which cells are born together, and when.
//
// Each birth event restarts the integrator, so cells laid within one birth interval are born together, at
// the middle of their birth times. The interval is the one asked for, or else a fifth of the beads' median
// conduction time constant (each bead's slices through its height together), made longer where the print
// would need more than about max_automatic_birth_events events.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "thermal/heat.hpp"
#include "thermal/mesh.hpp"

namespace beadtwin::thermal {

// Cells [the previous group's end, end) are born at time_s.
struct BirthGroup {
  std::size_t end = 0;
  double time_s = 0.0;
};

// When every cell is born, in groups.
struct BirthSchedule {
  double interval_s = 0.0;            // the birth interval used, s
  double automatic_interval_s = 0.0;  // a fifth of the median time constant, s (before any lengthening)
  std::vector<BirthGroup> groups;     // in time order; the last ends at the last cell
  std::string note;                   // why the automatic interval was made longer; empty if it was not
};

// The groups of `cells` (in birth order, at least one) born together. `median_time_constant_s`: the beads'
// median conduction time constant (C / ΣG), s, > 0. Uses options.birth_interval_s (0: automatic) and
// options.max_automatic_birth_events.
BirthSchedule plan_births(std::span<const ThermalCell> cells, double median_time_constant_s,
                          const HeatOptions& options);

}  // namespace beadtwin::thermal
