#include "thermal/wall_1d_model.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/units.hpp"

namespace beadtwin::thermal {

namespace {

constexpr double kM2PerMm2 = 1e-6;
constexpr double kMPerMm = 1e-3;

}  // namespace

Wall1dModel::Wall1dModel(std::span<const Wall1dLayer> layers, const Material& material,
                         const Environment& env, int nodes_per_layer, bool side_half_cell)
    : material_(material),
      n_(static_cast<std::size_t>(nodes_per_layer)),
      block_(n_ + 2),
      reptation_(material),
      deposition_temp_c_(material.deposition_temp_c),
      air_{.convection_W_m2K = env.convection_W_m2K,
           .eps_sigma = material.emissivity * kStefanBoltzmann_W_m2K4,
           .ambient_c = env.ambient_c,
           .radiant_c = env.ambient_c},
      bed_temp_c_(env.bed_temp_c),
      bed_conductance_W_K_(0.0) {
  BT_CHECK_OP(nodes_per_layer, >=, 1);
  BT_CHECK(!layers.empty());
  const double k = material.conductivity_through_W_mK;
  const double n = static_cast<double>(n_);
  layers_.reserve(layers.size());
  for (std::size_t i = 0; i < layers.size(); ++i) {
    const Wall1dLayer& in = layers[i];
    const double area_m2 = in.area_mm2 * kM2PerMm2;
    const double node_thickness_m = in.height_mm * kMPerMm / n;
    Layer layer;
    layer.area_m2 = area_m2;
    layer.node_mass_kg = material.density_kg_m3 * area_m2 * node_thickness_m;
    layer.inner_conductance_W_K = k * area_m2 / node_thickness_m;
    layer.side_area_node_m2 = in.perimeter_mm * kMPerMm * node_thickness_m;
    layer.top_r_m2K_W = 0.5 * node_thickness_m / k;
    layer.side_r_m2K_W = side_half_cell && in.perimeter_mm > 0.0
                             ? in.area_mm2 / in.perimeter_mm * kMPerMm / material.conductivity_across_W_mK
                             : 0.0;
    if (i > 0) {
      // Series conduction from the centre of the lower node to the centre of the upper one through the
      // contact area both layers share.
      const double below_half_m = layers[i - 1].height_mm * kMPerMm / (2.0 * n);
      const double above_half_m = node_thickness_m / 2.0;
      layer.below_conductance_W_K =
          k * std::min(area_m2, layers[i - 1].area_mm2 * kM2PerMm2) / (below_half_m + above_half_m);
      // Linear profile between the node centres: the interface lies below_half from the lower node.
      layer.below_weight = above_half_m / (below_half_m + above_half_m);
    }
    layers_.push_back(layer);
  }
  if (!env.bed_insulated)
    bed_conductance_W_K_ = layers_[0].area_m2 / (1.0 / env.bed_contact_W_m2K + layers_[0].top_r_m2K_W);
}

std::vector<double> Wall1dModel::initial_state() const {
  std::vector<double> y(size(), 0.0);
  // Unborn nodes keep whatever value they hold (their derivative is zero); the deposition temperature
  // keeps the error weights of the whole state alike.
  for (std::size_t i = 0; i < layers_.size(); ++i)
    for (std::size_t j = 0; j < n_; ++j) y[temp_index(i, j)] = deposition_temp_c_;
  return y;
}

void Wall1dModel::set_tolerances(double rel_tol, double abs_tol_k, double healing_abs_tol) {
  rel_tol_ = rel_tol;
  abs_tol_k_ = abs_tol_k;
  healing_abs_tol_ = healing_abs_tol;
}

void Wall1dModel::error_weights(std::span<const double> y, std::span<double> weights) {
  for (std::size_t i = 0; i < layers_.size(); ++i) {
    for (std::size_t j = 0; j < n_; ++j) {
      const std::size_t k = temp_index(i, j);
      weights[k] = 1.0 / (rel_tol_ * std::abs(y[k]) + abs_tol_k_);
    }
    // Energy lost: the absolute tolerance is the energy of abs_tol_k over the whole layer (its heat capacity
    // at the deposition temperature), so the balance is held to the accuracy of the temperatures.
    const std::size_t q = loss_index(i);
    weights[q] =
        1.0 / (rel_tol_ * std::abs(y[q]) +
               abs_tol_k_ * node_capacity_J_K(layers_[i], deposition_temp_c_) * static_cast<double>(n_));
    // Healing: what is reported is D_h = min(1, H^(1/4)), whose relative error is a quarter of H's. So H
    // gets 4 rel_tol, and once H is past 1 (fully healed) only staying past 1 matters: a tenth of the
    // margin is allowed on top. Without this, the healing integrals of hot interfaces, which grow to
    // hundreds, would set the step size for no reported accuracy.
    const std::size_t h = healing_index(i);
    const double healing = std::abs(y[h]);
    weights[h] = 1.0 / (healing_abs_tol_ + 4.0 * rel_tol_ * healing + 0.1 * std::max(0.0, healing - 1.0));
  }
}

void Wall1dModel::birth(std::size_t layer, std::span<double> y) {
  BT_CHECK_OP(layer, ==, born_);
  BT_CHECK_OP(layer, <, layers_.size());
  for (std::size_t j = 0; j < n_; ++j) y[temp_index(layer, j)] = deposition_temp_c_;
  y[healing_index(layer)] = 0.0;
  y[loss_index(layer)] = 0.0;
  ++born_;
}

double Wall1dModel::layer_mean_temp_c(std::size_t layer, std::span<const double> y) const {
  double sum = 0.0;
  for (std::size_t j = 0; j < n_; ++j) sum += y[temp_index(layer, j)];
  return sum / static_cast<double>(n_);
}

double Wall1dModel::substrate_temp_c(std::size_t layer, std::span<const double> y) const {
  BT_CHECK_OP(layer, >=, 1u);
  return y[temp_index(layer - 1, n_ - 1)];
}

double Wall1dModel::interface_temp_c(std::size_t layer, std::span<const double> y) const {
  BT_CHECK_OP(layer, >=, 1u);
  const double w = layers_[layer].below_weight;
  return w * y[temp_index(layer - 1, n_ - 1)] + (1.0 - w) * y[temp_index(layer, 0)];
}

double Wall1dModel::energy_in_J() const {
  const double per_kg = material_.enthalpy_J_kg(air_.ambient_c, deposition_temp_c_);
  double sum = 0.0;
  for (std::size_t i = 0; i < born_; ++i) sum += layers_[i].node_mass_kg * static_cast<double>(n_) * per_kg;
  return sum;
}

double Wall1dModel::energy_stored_J(std::span<const double> y) const {
  double sum = 0.0;
  for (std::size_t i = 0; i < born_; ++i)
    for (std::size_t j = 0; j < n_; ++j)
      sum += layers_[i].node_mass_kg * material_.enthalpy_J_kg(air_.ambient_c, y[temp_index(i, j)]);
  return sum;
}

double Wall1dModel::energy_lost_J(std::span<const double> y) const {
  double sum = 0.0;
  for (std::size_t i = 0; i < born_; ++i) sum += y[loss_index(i)];
  return sum;
}

double Wall1dModel::top_area_m2(std::size_t layer, std::size_t node) const {
  if (node + 1 != n_) return 0.0;
  const bool topmost = layer + 1 >= born_;
  return topmost ? layers_[layer].area_m2
                 : std::max(0.0, layers_[layer].area_m2 - layers_[layer + 1].area_m2);
}

double Wall1dModel::bed_conductance_W_K(std::size_t layer, std::size_t node) const {
  return layer == 0 && node == 0 ? bed_conductance_W_K_ : 0.0;
}

Wall1dModel::Loss Wall1dModel::loss(std::size_t layer, std::size_t node, double temp_c) const {
  const Layer& l = layers_[layer];
  const double bed = bed_conductance_W_K(layer, node);
  Loss out{.W = bed * (temp_c - bed_temp_c_), .W_K = bed};
  const FaceFlux side = face_flux(air_, temp_c, l.side_r_m2K_W);
  out.W += l.side_area_node_m2 * side.flux_W_m2;
  out.W_K += l.side_area_node_m2 * side.slope_W_m2K;
  const double top = top_area_m2(layer, node);
  if (top > 0.0) {
    const FaceFlux f = face_flux(air_, temp_c, l.top_r_m2K_W);
    out.W += top * f.flux_W_m2;
    out.W_K += top * f.slope_W_m2K;
  }
  return out;
}

void Wall1dModel::rhs(double /*t*/, std::span<const double> y, std::span<double> ydot) {
  std::fill(ydot.begin(), ydot.end(), 0.0);
  for (std::size_t i = 0; i < born_; ++i) {
    const Layer& layer = layers_[i];
    double lost_W = 0.0;
    for (std::size_t j = 0; j < n_; ++j) {
      const double temp = y[temp_index(i, j)];
      double heat_W = 0.0;
      if (j > 0) heat_W += layer.inner_conductance_W_K * (y[temp_index(i, j - 1)] - temp);
      if (j + 1 < n_) heat_W += layer.inner_conductance_W_K * (y[temp_index(i, j + 1)] - temp);
      if (j == 0 && i > 0) heat_W += layer.below_conductance_W_K * (y[temp_index(i - 1, n_ - 1)] - temp);
      if (j + 1 == n_ && i + 1 < born_)
        heat_W += layers_[i + 1].below_conductance_W_K * (y[temp_index(i + 1, 0)] - temp);
      const double lost = loss(i, j, temp).W;
      lost_W += lost;
      ydot[temp_index(i, j)] = (heat_W - lost) / node_capacity_J_K(layer, temp);
    }
    ydot[loss_index(i)] = lost_W;
    if (i > 0) ydot[healing_index(i)] = reptation_.rate_per_s(interface_temp_c(i, y));
  }
}

void Wall1dModel::jacobian(double /*t*/, std::span<const double> y, BandJacobian& jac) {
  for (std::size_t i = 0; i < born_; ++i) {
    const Layer& layer = layers_[i];
    for (std::size_t j = 0; j < n_; ++j) {
      const std::size_t row = temp_index(i, j);
      const double inv_c = 1.0 / node_capacity_J_K(layer, y[row]);
      double diagonal_W_K = 0.0;
      auto couple = [&](std::size_t col, double conductance) {
        jac.set(row, col, conductance * inv_c);
        diagonal_W_K -= conductance;
      };
      if (j > 0) couple(temp_index(i, j - 1), layer.inner_conductance_W_K);
      if (j + 1 < n_) couple(temp_index(i, j + 1), layer.inner_conductance_W_K);
      if (j == 0 && i > 0) couple(temp_index(i - 1, n_ - 1), layer.below_conductance_W_K);
      if (j + 1 == n_ && i + 1 < born_) couple(temp_index(i + 1, 0), layers_[i + 1].below_conductance_W_K);
      const double dloss = loss(i, j, y[row]).W_K;
      jac.set(row, row, (diagonal_W_K - dloss) * inv_c);
      jac.set(loss_index(i), row, dloss);
    }
    if (i > 0) {
      const double rate_slope = reptation_.rate_derivative(interface_temp_c(i, y));
      const double w = layer.below_weight;
      jac.set(healing_index(i), temp_index(i - 1, n_ - 1), rate_slope * w);
      jac.set(healing_index(i), temp_index(i, 0), rate_slope * (1.0 - w));
    }
  }
}

}  // namespace beadtwin::thermal
