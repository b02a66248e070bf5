#include "thermal/healing.hpp"

#include <algorithm>

#include "thermal/for_range.hpp"

namespace beadtwin::thermal {

HealingIntegrator::HealingIntegrator(const Material& material, const InterfaceIndex& index,
                                     std::span<const Material> more_laws)
    : reptation_(material) {
  laws_.push_back(reptation_);
  for (const Material& m : more_laws) laws_.emplace_back(m);
  double coldest = reptation_.min_temp_c();
  for (const Reptation& law : laws_) coldest = std::min(coldest, law.min_temp_c());
  warm_c_ = coldest - 1.0;
  integral_.assign(laws_.size(), std::vector<double>(index.size(), 0.0));
  reset_lumps(index);
}

bool HealingIntegrator::find(const InterfaceIndex& index, std::size_t born, std::span<const double> start,
                             std::span<const double> end) {
  for (std::size_t i = 0; i < born; ++i) warm_[i] = std::max(start[i], end[i]) >= warm_c_;
  healing_now_.clear();
  lumps_healing_now_.clear();
  for (std::size_t i = 0; i < born; ++i) {
    if (!warm_[i]) continue;
    if (index.has_inner(i)) lumps_healing_now_.push_back(static_cast<std::uint32_t>(i));
    for (const InterfaceIndex::CellInterface& c : index.of_cell(i)) {
      if (c.younger >= born) continue;
      if (c.other < i && warm_[c.other]) continue;  // counted from the other cell
      healing_now_.push_back(c.interface);
    }
  }
  return !healing_now_.empty() || !lumps_healing_now_.empty();
}

void HealingIntegrator::integrate(const InterfaceIndex& index, double half_s, std::span<const double> y0,
                                  std::span<const double> y1) {
  for_range(0, healing_now_.size(), [&](std::size_t e) {
    const std::uint32_t k = healing_now_[e];
    const double t0 = interface_temp(index, y0, k), t1 = interface_temp(index, y1, k);
    for (std::size_t law = 0; law < laws_.size(); ++law) {
      integral_[law][k] += half_s * laws_[law].rate_per_s(t0);
      integral_[law][k] += half_s * laws_[law].rate_per_s(t1);
    }
  });
  for (const std::uint32_t g : lumps_healing_now_)
    for (std::size_t law = 0; law < laws_.size(); ++law) {
      lump_integral_[law][g] += half_s * laws_[law].rate_per_s(y0[g]);
      lump_integral_[law][g] += half_s * laws_[law].rate_per_s(y1[g]);
    }
}

bool HealingIntegrator::any_warm(const InterfaceIndex& index, std::span<const double> state) const {
  for (std::uint32_t k = 0; k < index.size(); ++k)
    if (warm(index, state, k)) return true;
  return false;
}

void HealingIntegrator::flush_lumps(const InterfaceIndex& index) {
  for (std::size_t law = 0; law < laws_.size(); ++law) {
    for (std::size_t g = 0; g < index.model_cells(); ++g)
      for (const std::uint32_t k : index.inner(g)) integral_[law][k] += lump_integral_[law][g];
    std::fill(lump_integral_[law].begin(), lump_integral_[law].end(), 0.0);
  }
}

void HealingIntegrator::reset_lumps(const InterfaceIndex& index) {
  lump_integral_.assign(laws_.size(), std::vector<double>(index.model_cells(), 0.0));
  warm_.assign(index.model_cells(), 0);
}

}  // namespace beadtwin::thermal
