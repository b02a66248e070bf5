// The heat an open face loses when the temperature the model holds is not the surface's (docs/physics.md,
// cooling): the conduction through the half cell between a cell's centre and its face, in series with
// convection and radiation from the face to the air.
//
// A cell (or a node of the 1-D wall) holds one temperature T, at its centre. Its open face lies a depth d
// away, behind a resistance per area R = d / k_n (k_n the conductivity along the face's normal). The face
// is at the temperature T_s at which what reaches it by conduction leaves it to the air:
//
//     (T − T_s) / R = h (T_s − T∞) + ε σ F (T_s⁴ − T_r⁴)
//
// so the flux is never more than the air could take from a surface at T, and with R = 0 the face is at T.
// F is the share of the face's hemisphere that is not the part (thermal/view_factor.hpp) and T_r the mean
// radiant temperature of what it sees there (the air's, or between it and the table's): the rest of the
// hemisphere sees the part's other faces, taken at the face's own temperature (no net exchange).
// The same series circuit carries the table's contact: (T − T_bed) / (R + 1/h_bed).
#pragma once

#include "core/units.hpp"

namespace beadtwin::thermal {

// The air around an open face: convection coefficient, W/m²K; ε σ F (F the share of the hemisphere that is
// not the part, 1 for a face that sees nothing of it), W/m²K⁴; the air's temperature, °C; the mean radiant
// temperature of what the face sees beyond the part, °C (the air's when it sees only the surroundings).
struct AirSide {
  double convection_W_m2K = 0.0;
  double eps_sigma = 0.0;
  double ambient_c = 0.0;
  double radiant_c = 0.0;
};

// What one open face loses per area.
struct FaceFlux {
  double flux_W_m2 = 0.0;    // from the cell to the air, W/m² (negative when the air is warmer)
  double surface_c = 0.0;    // the face's temperature, °C
  double slope_W_m2K = 0.0;  // d(flux)/dT of the cell's temperature, W/m²K
};

// The flux out of a face at depth resistance `r_m2K_W` (>= 0) behind which the cell is at `temp_c`.
// Three Newton steps on the surface balance from its linearised solution: a fixed count, so that the flux is
// a smooth function of T for the integrator (the balance is met to well under 1e-9 K for any R and
// temperature a print sees).
inline FaceFlux face_flux(const AirSide& air, double temp_c, double r_m2K_W) {
  const double ta = air.ambient_c + kKelvinOffset;
  const double tr = air.radiant_c + kKelvinOffset;
  const double tr4 = tr * tr * tr * tr;
  const double h = air.convection_W_m2K, es = air.eps_sigma;
  const double t = temp_c + kKelvinOffset;
  // Radiation linearised about T: the surface between T and T_r by the series rule.
  const double h_rad = es * (t * t + tr * tr) * (t + tr);
  // A half cell a billionth of the air's resistance (or none: a face at the cell's temperature, or what
  // adding and removing faces' resistances leaves) changes nothing, and its huge conductance would only
  // cancel digits in the balance.
  if (!(r_m2K_W * (h + h_rad) > 1e-9)) {
    return {.flux_W_m2 = h * (temp_c - air.ambient_c) + es * (t * t * t * t - tr4),
            .surface_c = temp_c,
            .slope_W_m2K = h + 4.0 * es * t * t * t};
  }
  const double g = 1.0 / r_m2K_W;
  double ts = (g * t + h * ta + h_rad * tr) / (g + h + h_rad);
  double air_slope = 0.0;  // d(loss to the air)/dT_s
  for (int step = 0; step < 3; ++step) {
    const double ts3 = ts * ts * ts;
    const double residual = g * (t - ts) - h * (ts - ta) - es * (ts3 * ts - tr4);
    air_slope = h + 4.0 * es * ts3;
    ts += residual / (g + air_slope);
  }
  air_slope = h + 4.0 * es * ts * ts * ts;
  return {.flux_W_m2 = g * (t - ts),
          .surface_c = ts - kKelvinOffset,
          .slope_W_m2K = g * air_slope / (g + air_slope)};
}

}  // namespace beadtwin::thermal
