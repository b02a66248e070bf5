// The fusion window of an interface (docs/physics.md, fusion window): what the thermal models share.
//
// An interface is where a new bead lands on or against material laid before. It is too hot when the soft
// material under it cannot carry the bead and the roller (thermal/support.hpp: it slumps); too cold when it
// does not heal: the degree of healing of non-isothermal reptation (Yang & Pitchumani 2002), D_h = (∫ dt /
// t_w(T(t)))^¼ over the interface's temperature history, stays below the required healing. The reptation time
// is t_w(T) = t_ref · a(T) / a(T_ref), its shift a(T) by the material's law (HealingLaw): for amorphous
// polymers WLF from the glass transition T_g up to T_g + ΔT_WLF, log10 a = −C1 (T − T_g) / (C2 + T − T_g),
// and Arrhenius above it, ln a = E_a/R (1/T − 1/T_s) + ln a(T_s) at the switch T_s = T_g + ΔT_WLF,
// continuous there; or Arrhenius throughout.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include "core/enum_names.hpp"

#include "core/material.hpp"

namespace beadtwin::thermal {

constexpr double kGasConstant_J_molK = 8.314462618;
constexpr double kStefanBoltzmann_W_m2K4 = 5.670374419e-8;

// The verdict on an interface (judge_interface); kNoInterface for a cell that has none. kMarginal is no
// interface's verdict: it is what the reports and the fusion map show for an interface (a cell, a layer)
// whose verdict changes across the P10-P90 band of the inputs' plausible values (thermal/uncertainty.hpp).
enum class Verdict { kOk, kTooHot, kTooCold, kNoInterface, kMarginal };
std::string_view to_string(Verdict verdict);

// How the bands of the verdicts over the inputs' plausible ranges are estimated (thermal/uncertainty.hpp):
// not at all, or linearised from extra solves.
enum class UncertaintyMethod : std::uint8_t { kOff, kLinearised };
inline constexpr EnumName<UncertaintyMethod> kUncertaintyMethodNames[] = {
    {UncertaintyMethod::kOff, "off"}, {UncertaintyMethod::kLinearised, "linearised"}};
constexpr std::span<const EnumName<UncertaintyMethod>> enum_names(UncertaintyMethod) {
  return kUncertaintyMethodNames;
}

// Rate 1/t_w(T) of the healing integral; zero below the material's healing threshold (glassy: no healing)
// and where the WLF shift diverges (at or below T_g − C2).
class Reptation {
 public:
  explicit Reptation(const Material& material);
  double rate_per_s(double temp_c) const;  // at `temp_c`, °C
  // d(rate)/dT, 1/(s·K); zero below the threshold (the step at the threshold has no derivative). At the
  // switch from WLF to Arrhenius, the Arrhenius side's.
  double rate_derivative(double temp_c) const;
  double min_temp_c() const { return min_temp_c_; }  // the healing threshold, °C

  // ln(t_w(T) / t_ref) at `temp_c`, °C, whether or not it heals there (the threshold is not applied);
  // +infinity at or below T_g − C2 under the WLF law.
  double log_time(double temp_c) const;
  // The temperature, °C, at which log_time is `value` (its inverse: log_time falls as the temperature
  // rises); +infinity where no temperature is hot enough.
  double temp_at_log_time(double value) const;

 private:
  // ln a(T): the shift, relative to T_g under the WLF law.
  double log_shift(double temp_k) const;
  // d ln a / dT at `temp_k`, 1/K.
  double log_shift_slope(double temp_k) const;

  double min_temp_c_;
  double ref_time_s_;
  bool wlf_;
  double glass_k_;            // T_g, K
  double c1_ln_;              // C1 ln 10: the WLF shift in natural logarithms
  double c2_k_;               // C2, K
  double switch_k_;           // T_s: WLF below, Arrhenius above; +infinity under the Arrhenius law
  double switch_shift_;       // ln a(T_s)
  double activation_temp_k_;  // E_a / R
  double ref_shift_;          // ln a(T_ref)
};

// Reptation (welding) time t_w(T), s; +infinity below material.healing_min_temp_c (and where the WLF shift
// diverges).
double reptation_time_s(const Material& material, double temp_c);

// The verdict on an interface: too hot where the material under it does not carry it (`too_hot`,
// thermal/support.hpp), else too cold when its healing (min(1, D_h)) is below the required healing, else ok.
Verdict judge_interface(bool too_hot, double healing, const Material& material);

}  // namespace beadtwin::thermal
