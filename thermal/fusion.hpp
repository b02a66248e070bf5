// The fusion window of an interface (docs/physics.md, fusion window): what the thermal models share.
//
// An interface is where a new bead lands on or against material laid before. It is too hot when the
// substrate under it is above the material's support limit as the bead lands (it cannot carry the bead and
// the roller: slump, squash-out); too cold when it does not heal: the degree of healing of non-isothermal
// reptation (Yang & Pitchumani 2002), D_h = (∫ dt / t_w(T(t)))^¼ over the interface's temperature history,
// with the reptation time t_w(T) = t_ref · exp(E_a/R (1/T − 1/T_ref)), stays below the required healing.
#pragma once

#include <string_view>

#include "core/material.hpp"

namespace beadtwin::thermal {

constexpr double kGasConstant_J_molK = 8.314462618;
constexpr double kStefanBoltzmann_W_m2K4 = 5.670374419e-8;

// The verdict on an interface (judge_interface); kNoInterface for a cell that has none.
enum class Verdict { kOk, kTooHot, kTooCold, kNoInterface };
std::string_view to_string(Verdict verdict);

// Rate 1/t_w(T) of the healing integral; zero below the material's healing threshold (glassy: no healing).
class Reptation {
 public:
  explicit Reptation(const Material& material);
  double rate_per_s(double temp_c) const;  // at `temp_c`, °C
  // d(rate)/dT, 1/(s·K); zero below the threshold (the step at the threshold has no derivative).
  double rate_derivative(double temp_c) const;
  double min_temp_c() const { return min_temp_c_; }  // the healing threshold, °C

 private:
  double min_temp_c_;
  double ref_time_s_;
  double activation_temp_k_;  // E_a / R
  double inv_ref_temp_k_;     // 1 / T_ref
};

// Reptation (welding) time t_w(T), s; +infinity below material.healing_min_temp_c.
double reptation_time_s(const Material& material, double temp_c);

// The verdict on an interface: too hot when the substrate was above the support limit as the new bead
// landed (judged only where it lands on top: `on_top`), else too cold when its healing (min(1, D_h)) is below
// the required healing, else ok.
Verdict judge_interface(double substrate_c, bool on_top, double healing, const Material& material);

}  // namespace beadtwin::thermal
