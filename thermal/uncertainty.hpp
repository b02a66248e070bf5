// The uncertainty of the fusion verdicts (docs/physics.md, uncertainty of the verdicts): the P10-P90 band of
// every interface's substrate and surface temperature and healing over the plausible ranges of the inputs
// that decide them (Material::ranges, Environment::ranges), and its verdict at both ends of the bands.
//
// Linearised: each input's effect is its finite-difference sensitivity times its spread, the inputs
// independent, their variances added, the band mean ± 1.2816 standard deviations (normal). What the heat
// solve depends on costs one more heat solve per input (or per group that moves as one: the three
// conductivities by one factor; density and specific heat through their product, which is all the heat solve
// sees); the healing law's inputs cost one more healing integral each beside the base solve, over the same
// temperatures (exact for any change of the law); the reptation time costs nothing (ln ∫ dt/t_w moves by
// −Δ ln t_ref exactly); the required healing and the support limit move their thresholds. Healing is
// linearised in ln ∫ dt/t_w, smooth and uncapped, and only then capped: min(1, D_h) is monotone, so its P10
// and P90 are the capped ends.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/enum_names.hpp"
#include "core/material.hpp"
#include "thermal/heat.hpp"
#include "thermal/mesh.hpp"

namespace beadtwin::thermal {

// The z of the normal distribution's 90th percentile: P10, P90 = mean ∓ kZ90 · standard deviation.
constexpr double kZ90 = 1.2815515655446004;

// Mean and standard deviation of an input over its range, in the input's units.
struct Moments {
  double mean = 0.0, sd = 0.0;
};
// Of `range` about the input's `value` (a scale range's factors times the value). Uniform: (lo + hi) / 2,
// (hi − lo) / √12; log-uniform: (hi − lo) / ln(hi / lo), its second moment (hi² − lo²) / (2 ln(hi / lo));
// normal: the value and sigma.
Moments moments_of(const InputRange& range, double value);

// One input (or group moving as one) moved by a step within its range: the inputs so moved, and in the
// coordinate the sensitivity is taken in (the input's units, or a factor on it), the step, and the mean's
// offset from the value and the standard deviation over the range.
struct Perturbation {
  std::string name;  // the range's key (or the group's: conductivity, heat_capacity)
  double step = 0.0, mean_offset = 0.0, sd = 0.0;
  Material material;
  Environment environment;
};

// What the linearised estimate needs besides the base solve.
struct UncertaintyPlan {
  std::vector<Perturbation> heat;  // each one more heat solve
  std::vector<Perturbation>
      laws;                      // the healing law's inputs: one more healing integral each (their materials)
  Moments log_reptation_time;    // ln t_ref: mean's offset from the value and sd
  Moments log_required_healing;  // ln D_req: likewise
  Moments log_support;           // ln(viscosity · allowed slump): mean's offset and sd (the support's limit)
  std::vector<std::string> inputs;  // every input with a range that the estimate uses, in the files' words
  // The extra heat solves' tolerances, as factors on the base solve's (HeatOptions::rel_tol, abs_tol_k).
  double tolerance_factor = 1.0;
  // The healing laws of `laws`, for HeatOptions::healing_laws of the base solve.
  std::vector<Material> law_materials() const;
};

// The plan for `material` and `environment` (their ranges). `fan_used`: the part-cooling fan runs at some
// time (else its convection has no effect and costs no solve). An input without a range does not move.
UncertaintyPlan plan_uncertainty(const Material& material, const Environment& environment, bool fan_used);

// Fills the bands and the verdicts at both ends of `heat`'s interfaces. `heat` was solved on `mesh` with
// `options` and plan.law_materials() as its healing laws; each of plan.heat is solved the same way (the
// base's birth interval, no snapshots, no progress reports), two at a time where no MPI ranks share the
// solve. Interfaces that did not heal at all are taken at ∫ dt/t_w = 1e-12 (D_h = 0.001).
void estimate_bands(const UncertaintyPlan& plan, const ThermalMesh& mesh, std::size_t layer_count,
                    double end_s, const Material& material, const HeatOptions& options, HeatResult& heat);

// One interface's deviations from the base under one perturbation: substrate and surface temperature, K,
// and ln ∫ dt/t_w.
struct InterfaceShift {
  double substrate_k = 0.0, surface_k = 0.0, log_integral = 0.0;
};

// Accumulates an interface's linearised mean and variance of the three quantities and combines them with
// the thresholds' spreads into its bands and end verdicts (estimate_bands's arithmetic, exposed for tests).
class BandSum {
 public:
  explicit BandSum(const InterfaceResult& base);
  // Adds a perturbation's effect: `shift` caused by `step`, over an input with `mean_offset` and `sd`.
  void add(const InterfaceShift& shift, double step, double mean_offset, double sd);
  // Adds a shift of ln ∫ dt/t_w by an input whose own effect is linear: its mean offset and sd in ln I.
  void add_log_integral(double mean_offset, double sd);
  // Writes the bands and end verdicts into `r`, with the thresholds' spreads of `plan`.
  // `reptation`: the material's law (the slope that moves the support's limit).
  void finish(const UncertaintyPlan& plan, const Material& material, const Reptation& reptation,
              InterfaceResult& r) const;

 private:
  double mean_[3];  // substrate, surface, ln I
  double var_[3] = {0.0, 0.0, 0.0};
};

}  // namespace beadtwin::thermal
