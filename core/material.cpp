#include "core/material.hpp"

namespace beadtwin {

double Environment::convection_at(double height_mm) const {
  const auto& p = convection_by_height;
  if (p.empty()) return convection_W_m2K;
  if (height_mm <= p.front().first) return p.front().second;
  for (std::size_t i = 1; i < p.size(); ++i)
    if (height_mm <= p[i].first) {
      const double t = (height_mm - p[i - 1].first) / (p[i].first - p[i - 1].first);
      return p[i - 1].second + t * (p[i].second - p[i - 1].second);
    }
  return p.back().second;
}

}  // namespace beadtwin
