#include "thermal/uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string_view>

#include <tbb/parallel_for.h>

namespace beadtwin::thermal {
namespace {

constexpr double kLeastIntegral = 1e-12;  // ∫ dt/t_w taken for an interface that did not heal at all

double log_integral(double integral) {
  return std::log(std::max(integral, kLeastIntegral));
}

// The step within the range: one standard deviation towards the side the mean lies on (the longer side of
// a uniform range; always inside it, as √12 > 2).
double step_of(const Moments& m, double value) {
  return m.mean >= value ? m.sd : -m.sd;
}

// An input the heat solve depends on: its key, whether its sensitivity is taken for a factor on it (a
// coefficient) or in its own units (a temperature, the emissivity), its value, and how to move it.
struct HeatInput {
  const char* key;
  bool factor;
  double value;
  std::function<void(Material&, Environment&, double)> move;  // by a step in its coordinate
};

Perturbation perturbation(const std::string& name, const Moments& m, double value, bool factor,
                          const Material& material, const Environment& env) {
  Perturbation p{.name = name, .material = material, .environment = env};
  p.mean_offset = factor ? m.mean / value - 1.0 : m.mean - value;
  p.sd = factor ? m.sd / value : m.sd;
  p.step = step_of({p.mean_offset, p.sd}, 0.0);
  return p;
}

void scale_table(std::vector<std::pair<double, double>>& table, double factor) {
  for (auto& point : table) point.second *= factor;
}

// The heat inputs other than the heat capacity, which is density and specific heat together.
std::vector<HeatInput> heat_inputs(const Material& m, const Environment& e, bool fan_used) {
  std::vector<HeatInput> out = {
      {"conductivity", true, m.conductivity_through_W_mK,
       [](Material& mat, Environment&, double s) {
         mat.conductivity_along_W_mK *= 1.0 + s;
         mat.conductivity_across_W_mK *= 1.0 + s;
         mat.conductivity_through_W_mK *= 1.0 + s;
       }},
      {"emissivity", false, m.emissivity, [](Material& mat, Environment&, double s) { mat.emissivity += s; }},
      {"deposition_temp", false, m.deposition_temp_c,
       [](Material& mat, Environment&, double s) { mat.deposition_temp_c += s; }},
      {"environment.convection", true, e.convection_W_m2K,
       [](Material&, Environment& env, double s) {
         env.convection_W_m2K *= 1.0 + s;
         scale_table(env.convection_by_height, 1.0 + s);
       }},
      {"environment.ambient", false, e.ambient_c,
       [](Material&, Environment& env, double s) { env.ambient_c += s; }},
  };
  if (fan_used && e.fan_convection_W_m2K > 0.0)
    out.push_back({"environment.fan_convection", true, e.fan_convection_W_m2K,
                   [](Material&, Environment& env, double s) { env.fan_convection_W_m2K *= 1.0 + s; }});
  if (!e.bed_insulated) {
    out.push_back({"environment.bed_contact", true, e.bed_contact_W_m2K,
                   [](Material&, Environment& env, double s) { env.bed_contact_W_m2K *= 1.0 + s; }});
    out.push_back({"environment.bed_temp", false, e.bed_temp_c,
                   [](Material&, Environment& env, double s) { env.bed_temp_c += s; }});
  }
  return out;
}

// Density and specific heat: the heat solve sees their product alone, so one factor on it; the product's
// relative spread is the sum of theirs (first order).
void plan_heat_capacity(const Material& m, const Environment& e, UncertaintyPlan& plan) {
  Moments sum;  // of the factor − 1
  double var = 0.0;
  for (const auto& [key, value] : {std::pair<const char*, double>{"density", m.density_kg_m3},
                                   {"specific_heat", m.specific_heat_J_kgK}}) {
    const InputRange* r = find_range(m.ranges, key);
    if (r == nullptr) continue;
    const Moments mo = moments_of(*r, value);
    sum.mean += mo.mean / value - 1.0;
    var += (mo.sd / value) * (mo.sd / value);
    plan.inputs.emplace_back(key);
  }
  if (var <= 0.0) return;
  Perturbation p{.name = "heat_capacity", .material = m, .environment = e};
  p.mean_offset = sum.mean;
  p.sd = std::sqrt(var);
  p.step = step_of({p.mean_offset, p.sd}, 0.0);
  p.material.specific_heat_J_kgK *= 1.0 + p.step;
  scale_table(p.material.specific_heat_by_temp, 1.0 + p.step);
  plan.heat.push_back(std::move(p));
}

void plan_laws(const Material& m, const Environment& e, UncertaintyPlan& plan) {
  struct LawInput {
    const char* key;
    double value;
    void (*move)(Material&, double);
  };
  const LawInput inputs[] = {
      {"fusion.wlf_c1", m.wlf_c1, [](Material& mat, double s) { mat.wlf_c1 += s; }},
      {"fusion.wlf_c2", m.wlf_c2_k, [](Material& mat, double s) { mat.wlf_c2_k += s; }},
      {"fusion.activation_energy", m.healing_activation_J_mol,
       [](Material& mat, double s) { mat.healing_activation_J_mol += s; }},
      // The whole mobility curve moves with T_g, the healing threshold with it.
      {"glass_transition", m.glass_transition_c,
       [](Material& mat, double s) {
         mat.glass_transition_c += s;
         mat.healing_min_temp_c += s;
       }},
  };
  for (const LawInput& in : inputs) {
    const InputRange* r = find_range(m.ranges, in.key);
    if (r == nullptr) continue;
    plan.inputs.emplace_back(in.key);
    Perturbation p = perturbation(in.key, moments_of(*r, in.value), in.value, false, m, e);
    if (p.sd <= 0.0) continue;
    in.move(p.material, p.step);
    plan.laws.push_back(std::move(p));
  }
}

// ln of an input over its range: the mean's offset from ln(value) and the sd (exact for log-uniform, first
// order otherwise).
Moments log_moments(const InputRange* r, double value) {
  if (r == nullptr) return {};
  if (r->spread == Spread::kLogUniform) {
    const double f = r->scale ? 1.0 : 1.0 / value;
    const double lo = std::log(r->lo * f), hi = std::log(r->hi * f);
    return {0.5 * (lo + hi), (hi - lo) / std::sqrt(12.0)};
  }
  const Moments m = moments_of(*r, value);
  return {m.mean / value - 1.0, m.sd / value};
}

}  // namespace

Moments moments_of(const InputRange& range, double value) {
  const double f = range.scale ? value : 1.0;
  switch (range.spread) {
    case Spread::kUniform:
      return {0.5 * (range.lo + range.hi) * f, (range.hi - range.lo) / std::sqrt(12.0) * f};
    case Spread::kLogUniform: {
      const double lo = range.lo * f, hi = range.hi * f;
      if (hi <= lo) return {lo, 0.0};
      const double l = std::log(hi / lo);
      const double mean = (hi - lo) / l;
      const double second = (hi * hi - lo * lo) / (2.0 * l);
      return {mean, std::sqrt(std::max(0.0, second - mean * mean))};
    }
    case Spread::kNormal:
      return {value, range.sigma * f};
  }
  return {value, 0.0};
}

std::vector<Material> UncertaintyPlan::law_materials() const {
  std::vector<Material> out;
  for (const Perturbation& p : laws) out.push_back(p.material);
  return out;
}

UncertaintyPlan plan_uncertainty(const Material& material, const Environment& environment, bool fan_used) {
  UncertaintyPlan plan;
  for (const HeatInput& in : heat_inputs(material, environment, fan_used)) {
    const bool of_machine = std::string_view(in.key).starts_with("environment.");
    const InputRange* r = find_range(of_machine ? environment.ranges : material.ranges, in.key);
    if (r == nullptr) continue;
    plan.inputs.emplace_back(in.key);
    Perturbation p =
        perturbation(in.key, moments_of(*r, in.value), in.value, in.factor, material, environment);
    if (p.sd <= 0.0) continue;
    in.move(p.material, p.environment, p.step);
    plan.heat.push_back(std::move(p));
  }
  plan_heat_capacity(material, environment, plan);
  plan_laws(material, environment, plan);
  if (const InputRange* r = find_range(material.ranges, "fusion.reptation_time")) {
    plan.inputs.emplace_back("fusion.reptation_time");
    plan.log_reptation_time = log_moments(r, material.reptation_time_ref_s);
  }
  if (const InputRange* r = find_range(material.ranges, "fusion.required_healing")) {
    plan.inputs.emplace_back("fusion.required_healing");
    plan.log_required_healing = log_moments(r, material.required_healing);
  }
  // The support's limit moves with ln η_ref + ln(allowed slump) (thermal/support.hpp: the limit is where
  // η(T) = η_ref a(T) / a(T_ref) reaches a load over the allowed slump): their spreads add in logarithms.
  for (const auto& [key, value] : {std::pair{"fusion.viscosity", material.viscosity_ref_Pa_s},
                                   std::pair{"fusion.max_slump", material.max_slump}}) {
    if (const InputRange* r = find_range(material.ranges, key)) {
      plan.inputs.emplace_back(key);
      const Moments m = log_moments(r, value);
      plan.log_support.mean += m.mean;
      plan.log_support.sd = std::hypot(plan.log_support.sd, m.sd);
    }
  }
  return plan;
}

BandSum::BandSum(const InterfaceResult& base)
    : mean_{base.substrate_c, base.substrate_surface_c, log_integral(base.healing_integral)} {}

void BandSum::add(const InterfaceShift& shift, double step, double mean_offset, double sd) {
  const double d[3] = {shift.substrate_k, shift.surface_k, shift.log_integral};
  for (int q = 0; q < 3; ++q) {
    const double slope = d[q] / step;
    mean_[q] += slope * mean_offset;
    var_[q] += slope * slope * sd * sd;
  }
}

void BandSum::add_log_integral(double mean_offset, double sd) {
  mean_[2] += mean_offset;
  var_[2] += sd * sd;
}

void BandSum::finish(const UncertaintyPlan& plan, const Material& material, const Reptation& reptation,
                     InterfaceResult& r) const {
  const double sd_t = std::sqrt(var_[0]), sd_s = std::sqrt(var_[1]), sd_l = std::sqrt(var_[2]);
  if (r.on_top) {
    r.substrate_p10_c = mean_[0] - kZ90 * sd_t;
    r.substrate_p90_c = mean_[0] + kZ90 * sd_t;
    r.surface_p10_c = mean_[1] - kZ90 * sd_s;
    r.surface_p90_c = mean_[1] + kZ90 * sd_s;
  }
  r.healing_p10 = std::min(1.0, std::exp(0.25 * (mean_[2] - kZ90 * sd_l)));
  r.healing_p90 = std::min(1.0, std::exp(0.25 * (mean_[2] + kZ90 * sd_l)));
  // The margins to the thresholds, each with its threshold's spread, as the value they give against the
  // threshold as the file sets it: the verdict is then the one judge_interface gives.
  // Too hot where the substrate is above the temperature at which what is under it slumps by the allowed
  // amount (SupportResult::limit_c: the column under the bead shifted by one offset, as the band shifts
  // the substrate); that limit moves by Δ ln(η_ref · allowed) over the slope of ln a(T) there.
  double hot_mean = -std::numeric_limits<double>::infinity(), hot_sd = 0.0;
  if (r.on_top && std::isfinite(r.support.limit_c)) {
    const double lim = r.support.limit_c;
    const double slope = reptation.log_time(lim - 0.5) - reptation.log_time(lim + 0.5);  // −d ln a/dT, 1/K
    const Moments& ls = plan.log_support;
    const double lim_mean = slope > 0.0 ? lim + ls.mean / slope : lim;
    const double lim_sd = slope > 0.0 ? ls.sd / slope : 0.0;
    hot_mean = mean_[0] - lim_mean;
    hot_sd = std::hypot(sd_t, lim_sd);
  }
  const Moments& req = plan.log_required_healing;
  const double cold_mean = 0.25 * mean_[2] - req.mean, cold_sd = std::hypot(0.25 * sd_l, req.sd);
  const auto at = [&](double z) {
    const double healing = std::min(1.0, std::exp(cold_mean + z * cold_sd));
    return judge_interface(r.on_top && hot_mean + z * hot_sd > 0.0, healing, material);
  };
  r.verdict_cold = at(-kZ90);
  r.verdict_hot = at(kZ90);
}

void estimate_bands(const UncertaintyPlan& plan, const ThermalMesh& mesh, std::size_t layer_count,
                    double end_s, const Material& material, const HeatOptions& options, HeatResult& heat) {
  if (heat.interfaces.empty()) return;
  HeatOptions o = options;
  o.birth_interval_s = heat.birth_interval_s;
  o.snapshot_times_s.clear();
  o.progress = {};
  o.healing_laws.clear();
  o.sample_interval_s = std::max(o.sample_interval_s, 60.0);
  o.rel_tol = std::min(0.1, o.rel_tol * plan.tolerance_factor);
  o.abs_tol_k *= plan.tolerance_factor;
  std::vector<std::vector<InterfaceShift>> shifts(plan.heat.size());
  const auto solve = [&](std::size_t p) {
    const Perturbation& pert = plan.heat[p];
    const HeatResult r = solve_heat(mesh, layer_count, end_s, pert.material, pert.environment, o);
    shifts[p].reserve(r.interfaces.size());
    for (std::size_t k = 0; k < r.interfaces.size(); ++k) {
      const InterfaceResult& a = r.interfaces[k];
      const InterfaceResult& b = heat.interfaces[k];
      shifts[p].push_back({a.substrate_c - b.substrate_c, a.substrate_surface_c - b.substrate_surface_c,
                           log_integral(a.healing_integral) - log_integral(b.healing_integral)});
    }
  };
  if (options.communicator != nullptr && options.communicator->size() > 1) {
    for (std::size_t p = 0; p < plan.heat.size(); ++p) solve(p);
  } else {
    tbb::parallel_for(std::size_t{0}, plan.heat.size(), solve);
  }
  const Reptation reptation(material);
  for (std::size_t k = 0; k < heat.interfaces.size(); ++k) {
    InterfaceResult& r = heat.interfaces[k];
    BandSum sum(r);
    for (std::size_t p = 0; p < plan.heat.size(); ++p)
      sum.add(shifts[p][k], plan.heat[p].step, plan.heat[p].mean_offset, plan.heat[p].sd);
    for (std::size_t l = 0; l < plan.laws.size() && l < heat.law_integrals.size(); ++l) {
      const double d = log_integral(heat.law_integrals[l][k]) - log_integral(r.healing_integral);
      sum.add({.log_integral = d}, plan.laws[l].step, plan.laws[l].mean_offset, plan.laws[l].sd);
    }
    sum.add_log_integral(-plan.log_reptation_time.mean, plan.log_reptation_time.sd);
    sum.finish(plan, material, reptation, r);
  }
}

}  // namespace beadtwin::thermal
