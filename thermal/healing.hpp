// The healing integrator of the heat solve, internal to the thermal library (thermal/heat.hpp): the integral
// ∫ dt / t_w(T) of every interface over its temperature history, advanced after every step of the
// integrator.
//
// An interface heals only while one of its cells is warm (above the material's healing threshold, less a
// kelvin for what the interpolant does between a step's ends); over a step its integrand is integrated by
// two-point Gauss-Legendre quadrature on the integrator's own interpolant, at the mean of its two cells'
// temperatures. The integral goes on past 1 (full healing): how far past says how much colder the interface
// could be. An interface inside a lumped cell heals at that cell's temperature: integrated once per lumped
// cell, and handed to each of its inner interfaces when the cells are lumped again or at the end.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/material.hpp"
#include "thermal/fusion.hpp"
#include "thermal/interface_index.hpp"

namespace beadtwin::thermal {

// Integrates ∫ dt / t_w(T) of every interface over the integrator's steps, lumped cells included.
class HealingIntegrator {
 public:
  // For `index.size()` interfaces between `index.model_cells()` model cells, none healed yet: by `material`'s
  // reptation law, and beside it by each of `more_laws`' (integrals(law)) over the same temperatures.
  HealingIntegrator(const Material& material, const InterfaceIndex& index,
                    std::span<const Material> more_laws = {});

  // Which interfaces (and lumped cells) heal over a step from state `start` to state `end` (by model cell,
  // the first `born` born): those born (both cells) with a warm cell, each once. True if any.
  bool find(const InterfaceIndex& index, std::size_t born, std::span<const double> start,
            std::span<const double> end);
  // Adds their healing over the step: `half_s` half its length, s; y0 and y1 the states (by model cell) at
  // its two Gauss-Legendre points. The interfaces are shared out among TBB's threads, each summing its two
  // points in order, so the sums do not depend on the thread count.
  void integrate(const InterfaceIndex& index, double half_s, std::span<const double> y0,
                 std::span<const double> y1);

  // Hands each lumped cell's healing to its inner interfaces (in `index`, before the cells are lumped anew).
  void flush_lumps(const InterfaceIndex& index);
  // After the cells were lumped anew and `index` with them: its model cells, none of them healed yet.
  void reset_lumps(const InterfaceIndex& index);

  // Per interface, ∫ dt / t_w so far (all of it once the lumps are flushed): by the material's law, or by
  // more_laws[law - 1].
  std::span<const double> integrals(std::size_t law = 0) const { return integral_[law]; }

  // Whether interface k is at or above the healing threshold in `state` (by model cell, all of `index`'s
  // cells born): the mean of its two cells' temperatures, as it heals.
  bool warm(const InterfaceIndex& index, std::span<const double> state, std::uint32_t k) const {
    const auto& cells = index.cells(k);
    return 0.5 * (state[cells[0]] + state[cells[1]]) >= reptation_.min_temp_c();
  }
  // Whether any interface is (warm).
  bool any_warm(const InterfaceIndex& index, std::span<const double> state) const;

 private:
  static double interface_temp(const InterfaceIndex& index, std::span<const double> state, std::uint32_t k) {
    const auto& cells = index.cells(k);
    return 0.5 * (state[cells[0]] + state[cells[1]]);
  }

  Reptation reptation_;
  std::vector<Reptation> laws_;                     // the material's, then more_laws'
  double warm_c_;                                   // a cell above it may heal during a step (by any law)
  std::vector<std::vector<double>> integral_;       // [law][interface]
  std::vector<std::vector<double>> lump_integral_;  // [law][model cell]: ∫ dt / t_w since lumped
  std::vector<char> warm_;                          // per model cell, scratch of find
  std::vector<std::uint32_t> healing_now_, lumps_healing_now_;  // what find found
};

}  // namespace beadtwin::thermal
