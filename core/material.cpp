#include "core/material.hpp"

namespace beadtwin {

namespace {

// The value at x of the piecewise-linear function through `p`, constant beyond its ends.
double piecewise(const std::vector<std::pair<double, double>>& p, double x) {
  if (x <= p.front().first) return p.front().second;
  for (std::size_t i = 1; i < p.size(); ++i)
    if (x <= p[i].first) {
      const double t = (x - p[i - 1].first) / (p[i].first - p[i - 1].first);
      return p[i - 1].second + t * (p[i].second - p[i - 1].second);
    }
  return p.back().second;
}

// The integral of the piecewise-linear function through `p` from a to b (a <= b), exactly.
double piecewise_integral(const std::vector<std::pair<double, double>>& p, double a, double b) {
  // Breakpoints inside (a, b), then the trapezoids between consecutive points, each exact for a linear piece.
  double sum = 0.0, x = a, fx = piecewise(p, a);
  for (const auto& [xi, fi] : p) {
    if (xi <= a) continue;
    if (xi >= b) break;
    sum += 0.5 * (fx + fi) * (xi - x);
    x = xi;
    fx = fi;
  }
  return sum + 0.5 * (fx + piecewise(p, b)) * (b - x);
}

}  // namespace

double Material::specific_heat_at(double temp_c) const {
  return specific_heat_by_temp.empty() ? specific_heat_J_kgK : piecewise(specific_heat_by_temp, temp_c);
}

double Material::enthalpy_J_kg(double from_c, double to_c) const {
  if (specific_heat_by_temp.empty()) return specific_heat_J_kgK * (to_c - from_c);
  return from_c <= to_c ? piecewise_integral(specific_heat_by_temp, from_c, to_c)
                        : -piecewise_integral(specific_heat_by_temp, to_c, from_c);
}

const InputRange* find_range(std::span<const InputRange> ranges, std::string_view key) {
  for (const InputRange& r : ranges)
    if (r.key == key) return &r;
  return nullptr;
}

double Environment::convection_at(double height_mm) const {
  return convection_by_height.empty() ? convection_W_m2K : piecewise(convection_by_height, height_mm);
}

}  // namespace beadtwin
