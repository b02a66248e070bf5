#include "thermal/fusion.hpp"

#include <cmath>
#include <limits>

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
  }
  return "unknown";
}

Reptation::Reptation(const Material& material)
    : min_temp_c_(material.healing_min_temp_c),
      ref_time_s_(material.reptation_time_ref_s),
      activation_temp_k_(material.healing_activation_J_mol / kGasConstant_J_molK),
      inv_ref_temp_k_(1.0 / (material.healing_ref_temp_c + kKelvinOffset)) {}

double Reptation::rate_per_s(double temp_c) const {
  if (!(temp_c >= min_temp_c_)) return 0.0;
  return std::exp(-activation_temp_k_ * (1.0 / (temp_c + kKelvinOffset) - inv_ref_temp_k_)) / ref_time_s_;
}

double Reptation::rate_derivative(double temp_c) const {
  const double t_k = temp_c + kKelvinOffset;
  return rate_per_s(temp_c) * activation_temp_k_ / (t_k * t_k);
}

double reptation_time_s(const Material& material, double temp_c) {
  const double rate = Reptation(material).rate_per_s(temp_c);
  return rate > 0.0 ? 1.0 / rate : std::numeric_limits<double>::infinity();
}

Verdict judge_interface(double substrate_c, bool on_top, double healing, const Material& material) {
  if (on_top && substrate_c > material.support_limit_c) return Verdict::kTooHot;
  if (healing < material.required_healing) return Verdict::kTooCold;
  return Verdict::kOk;
}

}  // namespace beadtwin::thermal
