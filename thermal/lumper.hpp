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

// No bead column (LumpRules::column).
inline constexpr std::uint32_t kNoColumn = 0xFFFFFFFFu;

// What settled_runs lumps.
struct LumpRules {
  // Settled cells: runs of consecutive born cells, each far below the top (`depth` kFarBelowTop) and
  // touching the run before it, within `tolerance_k` of one another and of at most `max_mass_kg` together.
  bool settled = true;
  double tolerance_k = 0.5;
  double max_mass_kg = 0.0;
  // Covered beads: by model cell, the bead whose slices through its height it holds (the same number for
  // each of them; kNoColumn for a cell that holds none, or more than one bead's). Runs of consecutive born
  // cells of one bead that all lie at least `slice_depth` contacts below the top become one cell whatever
  // their temperatures: a bead cut into slices to resolve its cooling from the top while it is the top,
  // one cell again once beads have been laid over it. Empty: none.
  std::span<const std::uint32_t> column;
  int slice_depth = 4;
};

// The runs of `rules` among `model`'s cells in `state` (by cell, K), at `depth` (contacts_below_top): to[i]
// for every cell of the model, the run it falls in (non-decreasing; a run of one for every other cell).
// Returns the number of runs.
std::uint32_t settled_runs(const PartModel& model, std::span<const double> state,
                           std::span<const std::uint8_t> depth, const LumpRules& rules,
                           std::vector<std::uint32_t>& to);
// The settled cells alone.
inline std::uint32_t settled_runs(const PartModel& model, std::span<const double> state,
                                  std::span<const std::uint8_t> depth, double tolerance_k, double max_mass_kg,
                                  std::vector<std::uint32_t>& to) {
  return settled_runs(model, state, depth, {.tolerance_k = tolerance_k, .max_mass_kg = max_mass_kg}, to);
}

// Decides when to look for settled cells and which runs of them to lump.
class Lumper {
 public:
  // options' lump_check_cells, lump_depth, lump_slice_beads, lump_tolerance_k and lump_max_cells (with
  // `median_mass_kg`, the beads' median mass, and `slices_per_bead`, the most cells through a bead) set when
  // to look and what is settled.
  Lumper(const HeatOptions& options, double median_mass_kg, int slices_per_bead = 1);

  // The settled cells of `model` in `state` (by cell), as settled_runs' `to`, once enough cells have been
  // born since the last look (`mesh_born`: the mesh cells born so far; at least lump_check_cells and a
  // quarter of the model's born cells) and enough would go to be worth restarting the integrator; else
  // empty. With `column` (LumpRules::column) also the covered beads' slices, looked for more often (after
  // an eighth of lump_check_cells and a 32nd of the born cells), so that few covered slices wait.
  std::vector<std::uint32_t> settled(const PartModel& model, std::span<const double> state,
                                     std::size_t mesh_born, std::span<const std::uint32_t> column = {});

 private:
  std::size_t check_cells_;
  int depth_;
  int slice_depth_;
  double tolerance_k_;
  double max_mass_kg_;
  std::size_t born_at_check_ = 0, born_at_slice_check_ = 0;
};

}  // namespace beadtwin::thermal
