// The lumper of the heat solve, internal to the thermal library (thermal/heat.hpp, HeatOptions::lump;
// docs/physics.md, settled cells): which born cells have settled, far enough below the top and even enough
// in temperature that one temperature stands for a run of them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "thermal/heat.hpp"
#include "thermal/part_model.hpp"

namespace beadtwin::thermal {

// A depth no settled cell search reaches (contacts_below_top).
inline constexpr std::uint8_t kFarBelowTop = 255;

// Each born cell's distance in contacts from the top (the cells with a neighbour not yet born: 0), up to
// `max_depth` (1..254); kFarBelowTop for the cells further down, and for cells no path reaches.
std::vector<std::uint8_t> contacts_below_top(const PartModel& model, int max_depth);

// Runs of consecutive born cells, each far below the top (`depth` kFarBelowTop) and touching the run before
// it, within `tolerance_k` of one another in `state` (by cell, K) and of at most `max_mass_kg` together:
// to[i] for every cell of the model, the run it falls in (non-decreasing; a run of one for every other cell).
// Returns the number of runs.
std::uint32_t settled_runs(const PartModel& model, std::span<const double> state,
                           std::span<const std::uint8_t> depth, double tolerance_k, double max_mass_kg,
                           std::vector<std::uint32_t>& to);

// Decides when to look for settled cells and which runs of them to lump.
class Lumper {
 public:
  // options' lump_check_cells, lump_depth, lump_tolerance_k and lump_max_cells (with `median_mass_kg`, the
  // mesh cells' median mass) set when to look and what is settled.
  Lumper(const HeatOptions& options, double median_mass_kg);

  // The settled cells of `model` in `state` (by cell), as settled_runs' `to`, once enough cells have been
  // born since the last look (`mesh_born`: the mesh cells born so far; at least lump_check_cells and a
  // quarter of the model's born cells) and enough would go to be worth restarting the integrator; else
  // empty.
  std::vector<std::uint32_t> settled(const PartModel& model, std::span<const double> state,
                                     std::size_t mesh_born);

 private:
  std::size_t check_cells_;
  int depth_;
  double tolerance_k_;
  double max_mass_kg_;
  std::size_t born_at_check_ = 0;
};

}  // namespace beadtwin::thermal
