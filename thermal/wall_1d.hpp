// The 1-D reference model of a printed wall's thermal history and interlayer fusion (docs/physics.md,
// cooling and fusion window): the model the 3-D thermal stage (thermal/thermal.hpp) is checked against where
// the two make the same assumptions (tests/scenarios/compton_wall_test.cpp).
//
// The part is modelled as a 1-D stack of layers in the spirit of Compton et al. 2017 (Additive Manufacturing
// 17:77-86): each layer is `nodes_per_layer` control volumes through its thickness, with its footprint area
// and the length of its exposed side edges. A node's heat capacity is m c_p(T) (Material::specific_heat_at,
// the table when the material gives one), its energy m ∫ c_p dT, as in the 3-D model (thermal/heat.hpp). Heat
// is conducted through the stack (k through the layer thickness), lost by convection and radiation from the
// sides and from the exposed part of each layer's top, and exchanged with the table under layer 0, each
// through the half node between the node's centre and its face (thermal/surface.hpp): half a node's
// thickness (k through the layer) to the top and the table, and area / perimeter across the layer (k across
// the bead) to the sides, half the width of a straight wall. Layers appear by element birth: a whole layer
// is born at once, at its start time and at the deposition
// temperature, so the time a bead really waits before being covered is represented by the layer-to-layer
// period, not bead by bead.
//
// Integrated with SUNDIALS CVODE (BDF, banded direct solver), restarted at every birth. The healing of every
// interface follows the non-isothermal reptation model of Yang & Pitchumani 2002 (docs/physics.md, fusion
// window).
#pragma once

#include <span>
#include <string_view>
#include <vector>

#include "core/material.hpp"
#include "thermal/fusion.hpp"
#include "thermal/support.hpp"

namespace beadtwin::thermal {

// One layer of the wall as deposited.
struct Wall1dLayer {
  double z_top_mm = 0, height_mm = 0;
  double start_s = 0,
         end_s = 0;         // when the layer's deposition starts and ends; start times strictly increase
  double area_mm2 = 0;      // footprint of the layer (deposited volume / height), > 0
  double perimeter_mm = 0;  // length of the layer's exposed side edges (outer + inner contours), >= 0
};

// How solve_wall_1d integrates and samples.
struct Wall1dOptions {
  double rel_tol = 1e-6;         // CVODE relative tolerance
  double abs_tol_k = 1e-4;       // CVODE absolute tolerance on temperatures, K
  int nodes_per_layer = 2;       // nodes through each layer's thickness, >= 1
  double cooldown_s = 600;       // simulated time after the last layer (healing goes on), >= 0
  double sample_interval_s = 5;  // for the temperature history kept for plots, > 0
  SupportLoad support;           // the roller or tamper on each new layer (the too-hot verdict)
  // The sides lose heat through half the layer's width, as the 3-D model's open faces do through their
  // half cells; false: at the nodes' temperature, as a model resolving only the height has it.
  bool side_half_cell = true;
};

// What one layer's interface (with the layer below) went through.
struct Wall1dLayerResult {
  // Temperature of the layer below (its top node) while this layer is laid, over [start_s, end_s]: minimum,
  // time average and maximum, °C. Because the whole layer is born at start_s, this includes the reheating
  // of the substrate by the new layer, which grows as the top node gets closer to the interface (more
  // nodes per layer). Bed temperature for layer 0 (ambient on an insulated table).
  double substrate_min_c = 0, substrate_mean_c = 0, substrate_max_c = 0;
  // Temperature of the layer below's top node just before this layer touches it (at start_s), °C: the
  // substrate temperature at deposition, not affected by the reheating. Bed/ambient for layer 0.
  double substrate_at_start_c = 0;
  // The top face of the layer below at that moment, °C: what a thermal camera reads there
  // (thermal/surface.hpp).
  double surface_at_start_c = 0;
  // Degree of healing min(1, D_h) of the interface under this layer at the end of the simulation.
  // NaN for layer 0 (no interface).
  double healing = 0;
  // Whether the soft layers under this one carry it (thermal/support.hpp), judged just before it touches
  // them: the wall's width is 2 area / perimeter (a straight wall's), its speed the layer's length over its
  // deposition time, the soft layers' load time its start less the start of the deepest soft layer.
  SupportResult support;
  // support.too_hot(): kTooHot; else healing < required_healing: kTooCold; else kOk.
  Verdict verdict = Verdict::kNoInterface;
};

// What solve_wall_1d found.
struct Wall1dResult {
  std::vector<Wall1dLayerResult> layers;
  std::vector<double> sample_times_s;  // from the first layer's start to the end, every interval
  // [layer][sample] mean temperature of the layer, °C; NaN before the layer exists.
  std::vector<std::vector<float>> layer_temp_c;
  // Energy relative to ambient, J: brought in by births, lost through all boundaries (negative when the bed
  // heats the part), stored at the end; energy_balance_rel_error = |in − lost − stored| / max(|in|, |lost| +
  // |stored|), 0 when nothing moves.
  double energy_in_J = 0, energy_lost_J = 0, energy_stored_J = 0, energy_balance_rel_error = 0;
  long steps = 0;         // CVODE steps taken
  double end_time_s = 0;  // end of the simulation: last layer's end + cooldown
};

// Solves the thermal history of the layer stack. `layers` in deposition order (layer 0 on the table).
// Throws InputError naming the layer index or the field when an input cannot be used (all problems found
// are listed), InternalError when the integrator fails.
Wall1dResult solve_wall_1d(std::span<const Wall1dLayer> layers, const Material& material,
                           const Environment& env, const Wall1dOptions& options = {});

}  // namespace beadtwin::thermal
