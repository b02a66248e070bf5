// The analytic cooling of a lumped body with a temperature-dependent specific heat, shared by the tests of
// the 3-D heat solve (tests/thermal/heat_test.cpp) and of the 1-D reference model
// (tests/thermal/wall_1d_test.cpp).
//
// A body of one temperature cooling by convection alone obeys m c_p(T) dT/dt = −h A (T − T∞). Separating
// the variables (as in Incropera & DeWitt, Fundamentals of Heat and Mass Transfer, 6th ed., §5.1, the
// lumped capacitance method, with a capacity that varies), the time it takes to cool from T0 to T is
//
//     t(T) = (m / hA) ∫_T^T0 c_p(T') / (T' − T∞) dT'.
//
// With c_p piecewise linear in T (Material::specific_heat_by_temp, constant beyond its ends), each piece
// c_p = a + b θ, θ = T' − T∞, integrates in closed form: a ln(θ2/θ1) + b (θ2 − θ1).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <utility>
#include <vector>

#include "core/material.hpp"

namespace beadtwin::thermal {

// Time for a lumped body of `mass_kg` losing h A = `ha_W_K` to air at `ambient_c` to cool from `from_c` down
// to `to_c` (ambient_c < to_c <= from_c), s.
inline double lumped_cooling_time_s(const Material& m, double mass_kg, double ha_W_K, double ambient_c,
                                    double from_c, double to_c) {
  // The pieces: between to_c, the table's points inside (to_c, from_c), and from_c; c_p is linear on each.
  std::vector<double> x{to_c};
  for (const auto& point : m.specific_heat_by_temp)
    if (point.first > to_c && point.first < from_c) x.push_back(point.first);
  x.push_back(from_c);
  double integral = 0.0;  // ∫ c_p / θ dT over [to_c, from_c], J/kg·K
  for (std::size_t k = 0; k + 1 < x.size(); ++k) {
    const double theta0 = x[k] - ambient_c, theta1 = x[k + 1] - ambient_c;
    const double c0 = m.specific_heat_at(x[k]), c1 = m.specific_heat_at(x[k + 1]);
    const double b = (c1 - c0) / (theta1 - theta0);
    const double a = c0 - b * theta0;
    integral += a * std::log(theta1 / theta0) + b * (theta1 - theta0);
  }
  return mass_kg / ha_W_K * integral;
}

// The largest relative difference between the time a model took to reach each of its sampled temperatures
// (`times_s`, `temps_c`: a history starting at the deposition temperature `from_c`) and the time the
// separated-variable solution takes to reach it; the first sample (t = 0) is left out.
inline double max_time_error_fraction(const Material& m, double mass_kg, double ha_W_K, double ambient_c,
                                      double from_c, std::span<const double> times_s,
                                      std::span<const float> temps_c) {
  double worst = 0.0;
  for (std::size_t k = 1; k < times_s.size(); ++k) {
    const double exact =
        lumped_cooling_time_s(m, mass_kg, ha_W_K, ambient_c, from_c, static_cast<double>(temps_c[k]));
    worst = std::max(worst, std::abs(exact - times_s[k]) / times_s[k]);
  }
  return worst;
}

// A specific heat with a glass-transition step, as the shipped materials have (scenarios/data/materials):
// a glass whose c_p rises with temperature, a step of 400 J/kg·K over 5 K about 107.5 °C, and a melt whose
// c_p rises more slowly; constant below 20 °C and above 300 °C.
inline std::vector<std::pair<double, double>> glass_step_specific_heat() {
  return {{20.0, 1200.0}, {105.0, 1500.0}, {110.0, 1900.0}, {300.0, 2100.0}};
}

}  // namespace beadtwin::thermal
