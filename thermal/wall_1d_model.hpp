// The 1-D stacked-layer wall as an ODE system (internal to the thermal library; see wall_1d.hpp for the
// model). Everything here is SI: m, m², J, W, K for differences; temperatures in °C, converted to K where a
// formula needs absolute temperature (radiation, Arrhenius).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "core/material.hpp"
#include "thermal/cvode.hpp"
#include "thermal/fusion.hpp"
#include "thermal/surface.hpp"
#include "thermal/wall_1d.hpp"

namespace beadtwin::thermal {

// State layout: one block of (n + 2) entries per layer i, so that every coupling stays within a narrow
// band (upper bandwidth 3, lower max(3, n)):
//   [ H_i | T_i,0 (bottom) ... T_i,n-1 (top) | Q_i ]
// T in °C; H_i = ∫ dt / t_w(T_int) of the interface under layer i (unused for layer 0); Q_i = energy lost
// through layer i's boundaries since its birth, J. Entries of layers not yet born stay constant.
//
// Why the healing integrals are CVODE states rather than a quadrature of the sampled history: the
// integrand 1/t_w(T) changes by ~10 % per kelvin (E_a/(R T²)), so D_h is only as good as the interface
// temperature at every instant. As states they are advanced by the same BDF formula under the same local
// error test as the temperatures (with weights of their own, see error_weights), and the jump of the rate
// at the healing threshold is met by CVODE's step control instead of being smeared between samples. The
// energy lost is a state for the same reason: the balance in − lost − stored then checks the flux
// bookkeeping, not a post-processing rule. With a constant c_p the stored energy is linear in the state and
// BDF keeps the balance up to the Newton tolerance; with c_p(T) it is m ∫ c_p dT, and the balance holds to
// the integration error.
class Wall1dModel final : public OdeSystem {
 public:
  // `side_half_cell`: the sides lose heat through half the layer's width (else at the nodes' temperature).
  Wall1dModel(std::span<const Wall1dLayer> layers, const Material& material, const Environment& env,
              int nodes_per_layer, bool side_half_cell);

  // The state's size and the Jacobian's bandwidths (for the banded solver).
  std::size_t size() const { return layers_.size() * block_; }
  std::size_t upper_bandwidth() const { return 3; }
  std::size_t lower_bandwidth() const { return n_ > 3 ? n_ : 3; }
  // Where in the state a layer's node temperature (°C), healing integral and energy lost (J) are.
  std::size_t temp_index(std::size_t layer, std::size_t node) const { return layer * block_ + 1 + node; }
  std::size_t healing_index(std::size_t layer) const { return layer * block_; }
  std::size_t loss_index(std::size_t layer) const { return layer * block_ + 1 + n_; }
  std::size_t nodes_per_layer() const { return n_; }

  // The state before any birth: every temperature at the deposition temperature, nothing healed or lost.
  std::vector<double> initial_state() const;
  // Error control (see error_weights): relative tolerance, absolute tolerance on temperatures (K) and on
  // the healing integral H (dimensionless).
  void set_tolerances(double rel_tol, double abs_tol_k, double healing_abs_tol);

  // Births layer `layer` (the next one in order) in state y: its nodes at the deposition temperature.
  void birth(std::size_t layer, std::span<double> y);
  std::size_t born_count() const { return born_; }

  // The mean of the layer's node temperatures in state y, °C.
  double layer_mean_temp_c(std::size_t layer, std::span<const double> y) const;
  // Top node of the layer under `layer` (layer >= 1).
  double substrate_temp_c(std::size_t layer, std::span<const double> y) const;
  // The top face of the layer under `layer` (layer >= 1) while open to the air, °C.
  double substrate_surface_c(std::size_t layer, std::span<const double> y) const {
    return face_flux(air_, substrate_temp_c(layer, y), layers_[layer - 1].top_r_m2K_W).surface_c;
  }
  // Interface temperature under `layer` (layer >= 1): linear between the two adjacent node centres (the
  // mean of the two when the layers are equally thick).
  double interface_temp_c(std::size_t layer, std::span<const double> y) const;

  // Energies relative to ambient over the born layers, J.
  double energy_in_J() const;
  double energy_stored_J(std::span<const double> y) const;
  double energy_lost_J(std::span<const double> y) const;

  void rhs(double t, std::span<const double> y, std::span<double> ydot) override;
  void jacobian(double t, std::span<const double> y, BandJacobian& jacobian) override;
  void error_weights(std::span<const double> y, std::span<double> weights) override;

 private:
  struct Layer {
    double area_m2 = 0;
    double node_mass_kg = 0;           // ρ A h/n
    double inner_conductance_W_K = 0;  // between two nodes of this layer: k A / (h/n)
    double below_conductance_W_K = 0;  // to the layer below: k min(A) / (h_below/2n + h/2n)
    double below_weight = 0;           // weight of the lower node in the interface temperature
    double side_area_node_m2 = 0;      // perimeter · h/n
    double side_r_m2K_W = 0;           // half node across the layer: (area / perimeter) / k_across
    double top_r_m2K_W = 0;            // half node through it: (h/2n) / k_through
  };
  // Boundary loss of node j of layer i at temperature temp_c through its free surface (sides, and the
  // uncovered top for top nodes) and the bed (under layer 0), W, with its derivative with respect to the
  // temperature, W/K.
  struct Loss {
    double W = 0.0, W_K = 0.0;
  };
  Loss loss(std::size_t layer, std::size_t node, double temp_c) const;
  double top_area_m2(std::size_t layer, std::size_t node) const;
  // m c_p(T) of a node of `layer` at temperature temp_c, J/K. (The Jacobian leaves out the change of c_p
  // with T, as the 3-D model's does: Newton's matrix need not be exact.)
  double node_capacity_J_K(const Layer& layer, double temp_c) const {
    return layer.node_mass_kg * material_.specific_heat_at(temp_c);
  }
  double bed_conductance_W_K(std::size_t layer, std::size_t node) const;

  std::vector<Layer> layers_;
  Material material_;
  std::size_t n_;
  std::size_t block_;
  std::size_t born_ = 0;
  Reptation reptation_;
  double deposition_temp_c_;
  AirSide air_;
  double bed_temp_c_;
  double bed_conductance_W_K_;  // A_0 / (1/h_bed + half node), or 0 on an insulated table
  double rel_tol_ = 1e-6;
  double abs_tol_k_ = 1e-4;
  double healing_abs_tol_ = 1e-8;
};

}  // namespace beadtwin::thermal
