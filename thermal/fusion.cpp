#include "thermal/fusion.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/units.hpp"

namespace beadtwin::thermal {

std::string_view to_string(Verdict verdict) {
  switch (verdict) {
    case Verdict::kOk:
      return "ok";
    case Verdict::kTooHot:
      return "too_hot";
    case Verdict::kTooCold:
      return "too_cold";
    case Verdict::kNoInterface:
      return "no_interface";
    case Verdict::kMarginal:
      return "marginal";
  }
  return "unknown";
}

Reptation::Reptation(const Material& material)
    : min_temp_c_(material.healing_min_temp_c),
      ref_time_s_(material.reptation_time_ref_s),
      wlf_(material.healing_law == HealingLaw::kWlf),
      glass_k_(material.glass_transition_c + kKelvinOffset),
      c1_ln_(material.wlf_c1 * std::log(10.0)),
      c2_k_(material.wlf_c2_k),
      switch_k_(glass_k_ + material.wlf_range_k),
      switch_shift_(-c1_ln_ * material.wlf_range_k / (c2_k_ + material.wlf_range_k)),
      activation_temp_k_(material.healing_activation_J_mol / kGasConstant_J_molK),
      ref_shift_(log_shift(material.healing_ref_temp_c + kKelvinOffset)) {
  if (!std::isfinite(ref_shift_))
    throw InputError({}, "fusion.healing_ref_temp",
                     fmt::format("{} C is where the WLF shift diverges (at or below T_g - C2 = {} C)",
                                 material.healing_ref_temp_c, glass_k_ - c2_k_ - kKelvinOffset));
}

double Reptation::log_shift(double temp_k) const {
  if (!wlf_) return activation_temp_k_ / temp_k;
  if (temp_k > switch_k_) return switch_shift_ + activation_temp_k_ * (1.0 / temp_k - 1.0 / switch_k_);
  const double above = temp_k - glass_k_;
  if (!(above > -c2_k_)) return std::numeric_limits<double>::infinity();
  return -c1_ln_ * above / (c2_k_ + above);
}

double Reptation::log_shift_slope(double temp_k) const {
  if (!wlf_ || temp_k >= switch_k_) return -activation_temp_k_ / (temp_k * temp_k);
  const double denominator = c2_k_ + temp_k - glass_k_;
  return -c1_ln_ * c2_k_ / (denominator * denominator);
}

double Reptation::log_time(double temp_c) const {
  return log_shift(temp_c + kKelvinOffset) - ref_shift_;
}

double Reptation::temp_at_log_time(double value) const {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  const double shift = value + ref_shift_;
  if (wlf_ && shift > switch_shift_) {  // the WLF range: log10 a = −C1 x / (C2 + x) solved for x = T − T_g
    if (shift == kInfinity) return glass_k_ - c2_k_ - kKelvinOffset;
    return glass_k_ - shift * c2_k_ / (shift + c1_ln_) - kKelvinOffset;
  }
  if (!(activation_temp_k_ > 0.0)) return kInfinity;
  const double inverse =
      wlf_ ? 1.0 / switch_k_ + (shift - switch_shift_) / activation_temp_k_ : shift / activation_temp_k_;
  return inverse > 0.0 ? 1.0 / inverse - kKelvinOffset : kInfinity;
}

double Reptation::rate_per_s(double temp_c) const {
  if (!(temp_c >= min_temp_c_)) return 0.0;
  const double shift = log_shift(temp_c + kKelvinOffset);
  return std::isfinite(shift) ? std::exp(ref_shift_ - shift) / ref_time_s_ : 0.0;
}

double Reptation::rate_derivative(double temp_c) const {
  const double rate = rate_per_s(temp_c);
  return rate > 0.0 ? -rate * log_shift_slope(temp_c + kKelvinOffset) : 0.0;
}

double reptation_time_s(const Material& material, double temp_c) {
  const double rate = Reptation(material).rate_per_s(temp_c);
  return rate > 0.0 ? 1.0 / rate : std::numeric_limits<double>::infinity();
}

Verdict judge_interface(bool too_hot, double healing, const Material& material) {
  if (too_hot) return Verdict::kTooHot;
  return healing < material.required_healing ? Verdict::kTooCold : Verdict::kOk;
}

}  // namespace beadtwin::thermal
