#include "thermal/lumper.hpp"

#include <algorithm>
#include <utility>

namespace beadtwin::thermal {

std::vector<std::uint8_t> contacts_below_top(const PartModel& model, int max_depth) {
  const std::size_t born = model.born();
  std::vector<std::uint8_t> depth(born, kFarBelowTop);
  std::vector<std::uint32_t> front, next_front;
  for (std::size_t i = 0; i < born; ++i)
    if (model.on_top(i)) depth[i] = 0, front.push_back(static_cast<std::uint32_t>(i));
  for (int d = 1; d <= max_depth && !front.empty(); ++d) {
    next_front.clear();
    for (const std::uint32_t i : front)
      for (const std::uint32_t j : model.neighbours(i))
        if (j < born && depth[j] == kFarBelowTop)
          depth[j] = static_cast<std::uint8_t>(d), next_front.push_back(j);
    std::swap(front, next_front);
  }
  return depth;
}

std::uint32_t settled_runs(const PartModel& model, std::span<const double> state,
                           std::span<const std::uint8_t> depth, const LumpRules& rules,
                           std::vector<std::uint32_t>& to) {
  const std::size_t born = model.born();
  const std::size_t m = model.size_of_model();
  const auto covered = [&](std::size_t k) {
    return k < born && k < rules.column.size() && rules.column[k] != kNoColumn &&
           depth[k] >= rules.slice_depth;
  };
  to.resize(m);
  std::uint32_t g = 0;
  std::size_t i = 0;
  while (i < m) {
    std::size_t j = i + 1;
    if (covered(i))
      while (covered(j) && rules.column[j] == rules.column[i]) ++j;
    if (j == i + 1 && rules.settled && i < born && depth[i] == kFarBelowTop) {
      double lo = state[i], hi = state[i], mass = model.mass_kg(i);
      for (; j < born && depth[j] == kFarBelowTop; ++j) {
        const double t = state[j];
        if (std::max(hi, t) - std::min(lo, t) > rules.tolerance_k) break;
        if (mass + model.mass_kg(j) > rules.max_mass_kg) break;
        const auto nb = model.neighbours(j);
        const auto it = std::lower_bound(nb.begin(), nb.end(), static_cast<std::uint32_t>(i));
        if (it == nb.end() || *it >= j) break;  // does not touch the run
        lo = std::min(lo, t), hi = std::max(hi, t), mass += model.mass_kg(j);
      }
    }
    for (std::size_t k = i; k < j; ++k) to[k] = g;
    ++g;
    i = j;
  }
  return g;
}

Lumper::Lumper(const HeatOptions& options, double median_mass_kg, int slices_per_bead)
    : check_cells_(options.lump_check_cells),
      depth_(options.lump_depth),
      slice_depth_(std::min(options.lump_slice_beads * slices_per_bead, options.lump_depth)),
      tolerance_k_(options.lump_tolerance_k),
      max_mass_kg_(options.lump_max_cells * median_mass_kg) {}

std::vector<std::uint32_t> Lumper::settled(const PartModel& model, std::span<const double> state,
                                           std::size_t mesh_born, std::span<const std::uint32_t> column) {
  const std::size_t born = model.born();
  const bool settled_due = mesh_born >= born_at_check_ + std::max(check_cells_, born / 4);
  const bool slices_due =
      !column.empty() && mesh_born >= born_at_slice_check_ + std::max(check_cells_ / 8, born / 32);
  if (!settled_due && !slices_due) return {};
  if (settled_due) born_at_check_ = mesh_born;
  if (!column.empty()) born_at_slice_check_ = mesh_born;
  const std::vector<std::uint8_t> depth = contacts_below_top(model, depth_);
  const LumpRules rules{.settled = settled_due,
                        .tolerance_k = tolerance_k_,
                        .max_mass_kg = max_mass_kg_,
                        .column = column,
                        .slice_depth = slice_depth_};
  std::vector<std::uint32_t> to;
  const std::uint32_t runs = settled_runs(model, state, depth, rules, to);
  // Not worth a restart below this: with slices to merge, any (their looks come at births, which set the
  // integrator going anew in any case).
  const std::size_t least = column.empty() ? std::max<std::size_t>(64, born / 16) : 1;
  if (model.size_of_model() - runs < least) return {};
  return to;
}

}  // namespace beadtwin::thermal
