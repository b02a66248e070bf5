// The printed part as an ODE system for CVODE, internal to the thermal library (thermal/heat.hpp describes
// the model): each cell's temperature and the energy lost through the boundary, the births that add cells,
// and the lumping of settled cells into one.
//
// State: y = [T_0 .. T_{n-1} (°C) | Q (J lost through the boundary)]. Cells are in birth order, so the born
// ones are the first born(). Units inside: m, m², kg, J, W; temperatures in °C, in K where radiation needs
// absolute temperature.
//
// Across ranks (set_communicator) each rank integrates a contiguous block of the cells, [lo_, hi_), and its
// own share of Q: its part of the state is [T_lo .. T_{hi-1} | Q_rank], and the energy lost is the sum of
// the ranks' shares. Cells in birth order are cells by height, so the blocks are slices of the part, bottom
// to top. Each right-hand side and Jacobian product first brings in, from the other ranks, the temperatures
// of the cells its own cells touch (the halo).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/material.hpp"
#include "core/units.hpp"
#include "thermal/communicator.hpp"
#include "thermal/cvode.hpp"
#include "thermal/fusion.hpp"
#include "thermal/mesh.hpp"
#include "thermal/surface.hpp"

namespace beadtwin::thermal {

// The part's cells as the ODE system of the heat solve.
class PartModel final : public OdeSystem {
 public:
  // The cells and contacts of `mesh`, none born yet: every contact is open surface until its neighbour is
  // born. Conductances from the material's orthotropic conductivity (thermal/heat.hpp).
  PartModel(const ThermalMesh& mesh, const Material& material, const Environment& env);

  // The integrator's state: the first `capacity` cells (the born ones and room for the next) and the energy
  // lost, at index capacity. Every vector operation of a step runs over it, so it grows with the print.
  // Shares it among the ranks anew (the cells born so far set the blocks). born() <= capacity <= cells.
  void set_capacity(std::size_t capacity);
  std::size_t capacity() const { return cap_; }
  // Shares the state among `comm`'s ranks; null or one rank: all on this one.
  void set_communicator(Communicator* comm) { comm_ = comm != nullptr && comm->size() > 1 ? comm : nullptr; }
  Communicator* communicator() const { return comm_; }

  // This rank's part of a state of all cells (the first capacity() and the energy lost): its cells, and the
  // energy lost on rank 0 (0 on the others, so that the ranks' shares add up to it).
  std::vector<double> local(std::span<const double> full) const;
  // The state of all cells from every rank's part (`local` is this rank's): in `buffer`, or `local` itself
  // on one rank.
  std::span<const double> gather(std::span<const double> local, std::vector<double>& buffer) const;
  std::size_t born() const { return born_; }  // cells born so far: [0, born())
  // C / ΣG of cell i over all its contacts, s.
  double time_constant_s(std::size_t i) const;
  // The same of `cells` taken together, as lump would make them with recentre: their heat capacity over
  // their contacts with every other cell and the table, s.
  double time_constant_s(std::span<const std::uint32_t> cells) const;

  // Cells [born(), end) are born: each at its birth temperature in y, their faces towards born cells closed.
  void birth(std::size_t end, std::span<double> y);
  // Model cell i's temperature as it is born, °C: the deposition temperature and its cell's offset
  // (ThermalCell::deposition_offset_k).
  double birth_c(std::size_t i) const { return birth_c_[i]; }

  // The model's cells: the mesh's, less what lumping took.
  std::size_t size_of_model() const { return n_; }
  double mass_kg(std::size_t i) const { return mass_kg_[i]; }  // of model cell i
  // Whether cell i has a neighbour not yet born (neighbours are sorted, so the last tells).
  bool on_top(std::size_t i) const {
    return first_[i] != first_[i + 1] && nb_cell_[first_[i + 1] - 1] >= born_;
  }
  // Cell i's neighbours, in increasing order.
  std::span<const std::uint32_t> neighbours(std::size_t i) const {
    return {nb_cell_.data() + first_[i], nb_cell_.data() + first_[i + 1]};
  }

  // Lumps runs of born cells into one cell each (thermal/heat.hpp, settled cells): `to[i]`, for every cell,
  // is its cell afterwards, non-decreasing, equal only within a run, one to one for the cells not yet born.
  // A lumped cell has its members' mass, open and table surface and contacts (summed per neighbour; the
  // contacts between members go); its temperature is the one at which it holds its members' enthalpy, so the
  // energy stored does not change. `y` (the first capacity() cells) becomes the new cells' state; the energy
  // lost, after it, is carried over. A new cell g with `recentre[g]` (the slices of one bead through its
  // height: LumpRules::column) conducts from its own centroid: each contact's half on its side, and the half
  // cell down to the table, runs from the lumped cell's centroid rather than its member's, so that a bead of
  // two slices lumped conducts as a bead of one cell would (without it the lump would keep its top slice's
  // short path to the bead above). Empty: none.
  void lump(std::span<const std::uint32_t> to, std::vector<double>& y,
            std::span<const std::uint8_t> recentre = {});

  // Energy relative to ambient brought in by the births so far, J.
  double energy_in_J() const { return energy_in_J_; }
  // Energy relative to ambient held by the born cells in state y (indexed by cell), J.
  double energy_stored_J(std::span<const double> y) const;

  // The error test's tolerances: relative, and absolute on temperatures, K (on the energy lost: the
  // absolute tolerance times the part's heat capacity).
  void set_tolerances(double rel_tol, double abs_tol_k);

  // dT/dt of born cell i in state y (indexed by cell), K/s; its boundary loss, W, in `loss`.
  double rate(std::size_t i, const double* y, double& loss) const {
    const double t = y[i];
    double flux = 0.0;
    for (std::size_t k = first_[i], e = born_end_[i]; k < e; ++k) flux += nb_g_[k] * (y[nb_cell_[k]] - t);
    loss = table_W_K_[i] * (t - bed_c_);
    if (exposed_m2_[i] > 0.0) loss += exposed_m2_[i] * open_face(i, t).flux_W_m2;
    return (flux - loss) / heat_capacity(i, t);
  }
  // The open surface of model cell i when the cell is at `t` (°C): its flux, temperature and slope
  // (thermal/surface.hpp), through the half cell of all its open faces together (their resistances averaged
  // by area).
  FaceFlux open_face(std::size_t i, double t) const {
    return face_flux(air(i), t, exposed_m2_[i] > 0.0 ? exposed_rarea_[i] / exposed_m2_[i] : 0.0);
  }
  // The temperature of model cell i's open face towards cell j (a neighbour not yet born) when cell i is
  // at `t`, °C: what a thermal camera sees there before j covers it.
  double face_surface_c(std::size_t i, std::uint32_t j, double t) const {
    const std::size_t k = face_towards(i, j);
    return face_flux(air(i), t, nb_area_m2_[k] > 0.0 ? nb_rarea_[k] / nb_area_m2_[k] : 0.0).surface_c;
  }
  // The air side of model cell i's open faces: the mean of their views (thermal/view_factor.hpp), the faces
  // towards neighbours not yet born taken as seeing the sky.
  AirSide air(std::size_t i) const {
    return {.convection_W_m2K = std::max(h_[i], fan_h_),
            .eps_sigma = eps_sigma_view_[i],
            .ambient_c = ambient_c_,
            .radiant_c = radiant_c_[i]};
  }
  // Adds to model cell i's surface for good the views `sky_m2` and `table_m2`: its area times the change of
  // its sky and table view factors, m². Every cell starts seeing only the sky (sky: its area, table: 0).
  void add_view(std::size_t i, double sky_m2, double table_m2) {
    sky_m2_[i] += sky_m2;
    table_view_m2_[i] += table_m2;
    update_air(i);
  }
  // The part-cooling fan at `output` (0..1) of its full forced convection from now on.
  void set_fan(double output) { fan_h_ = output * fan_full_h_; }

  // The vectors below are this rank's part of the state: cell i at [i − lo_], its share of Q last.
  void rhs(double t, std::span<const double> y, std::span<double> ydot) override;
  // What every product of a linear solve shares: each cell's heat capacity and boundary loss derivative at
  // the solve's y (CVODE calls this before each solve: cvode.hpp). Kept as they are, not as reciprocals,
  // so a product is the same to the last bit as one working them out itself.
  void jacobian_times_setup(double t, std::span<const double> y) override;
  void jacobian_times(double t, std::span<const double> y, std::span<const double> v,
                      std::span<double> jv) override;
  void jacobian_diagonal(double t, std::span<const double> y, std::span<double> diagonal) override;
  void error_weights(std::span<const double> y, std::span<double> weights) override;

 private:
  // m c_p(T) of cell i, J/K. (The Jacobian leaves out the change of c_p with T: Newton's matrix need not
  // be exact.)
  double heat_capacity(std::size_t i, double t) const { return mass_kg_[i] * material_.specific_heat_at(t); }

  // d(loss)/dT of cell i at temperature t, W/K.
  double loss_derivative(std::size_t i, double t) const {
    return (exposed_m2_[i] > 0.0 ? exposed_m2_[i] * open_face(i, t).slope_W_m2K : 0.0) + table_W_K_[i];
  }

  // The contacts of `mesh` as neighbour lists (first_, nb_*), each sorted by neighbour.
  void list_neighbours(const ThermalMesh& mesh, const Material& material);
  // The lumped cells' contacts (see lump): the members' lists renumbered by `to` and merged per neighbour,
  // into the neighbour lists of the m cells afterwards (`centroid_mm`: theirs; `recentre` as for lump).
  void merge_neighbours(std::span<const std::uint32_t> to, std::size_t m,
                        std::span<const Eigen::Vector3d> centroid_mm, std::span<const std::uint8_t> recentre,
                        std::vector<std::size_t>& first, std::vector<Eigen::Vector3f>& nb_w,
                        std::vector<std::uint32_t>& nb_cell, std::vector<double>& nb_g,
                        std::vector<double>& nb_area, std::vector<double>& nb_rarea) const;
  void find_born_end(std::size_t i);
  // How much further cell i's contact k lies from `centroid_mm` than from i's own centroid, over i's
  // conductivity along the contact's normal (i's half of its resistance times the area, m²K/W).
  double half_shift(std::size_t i, std::size_t k, const Eigen::Vector3d& centroid_mm) const;
  // Cell i's contact with the table (table_W_K_, > 0) from a centroid at height `centroid_z_mm`, W/K.
  double table_from(std::size_t i, double centroid_z_mm) const;
  // Cell i's contact k (an index into its neighbour lists) is no longer open surface: its neighbour is born.
  void close_face(std::size_t i, std::size_t k) {
    exposed_m2_[i] -= nb_area_m2_[k];
    exposed_rarea_[i] -= nb_rarea_[k];
    update_air(i);
  }
  // Cell i's ε σ F and mean radiant temperature from its open faces' views (air).
  void update_air(std::size_t i);
  // The index of neighbour `j` in cell i's neighbour lists (which hold it).
  std::size_t face_towards(std::size_t i, std::uint32_t j) const;

  // The end of this rank's born cells: [lo_, owned_born()).
  std::size_t owned_born() const { return std::clamp(born_, lo_, hi_); }

  // The blocks of the ranks: rank r integrates cells [bounds_[r], bounds_[r + 1]). Between two rebuilds of
  // the integrator the born cells grow from born_ towards cap_, so the blocks share out the cells born on
  // average over that time, (born_ + cap_) / 2, and the last block takes the rest. With several ranks, also
  // the halo: which of its cells each rank sends to which, and which it receives.
  void partition();
  void partition_halo(std::size_t ranks, std::size_t me);

  // Values of a vector by cell for this rank's cells and its halo: `local` itself on one rank; else `all`,
  // its block copied in and the halo brought from the other ranks.
  const double* with_halo(std::span<const double> local, std::vector<double>& all) const;

  std::size_t n_;
  std::vector<double> mass_kg_;
  Material material_;
  std::vector<double> exposed_m2_;  // open now: for good, and towards neighbours not yet born
  // Σ area × half-cell resistance of those faces, m²·m²K/W (thermal/surface.hpp)
  std::vector<double> exposed_rarea_;
  std::vector<double> table_W_K_;      // to the table: its contact in series with the half cell down to it
  std::vector<double> table_area_m2_;  // resting on the table
  // The surface for good (open to the air whatever is born), m², and its area times its sky and table view
  // factors, m²; from them and exposed_m2_, the air side's ε σ F and mean radiant temperature, °C.
  std::vector<double> open_m2_, sky_m2_, table_view_m2_, eps_sigma_view_, radiant_c_;
  std::vector<std::size_t> first_;
  // Neighbours of cell i at [first_[i], first_[i + 1]), by index: who, the conductance, the contact area,
  // and that area times cell i's half-cell resistance to it (m²·m²K/W, while the contact is open surface).
  std::vector<std::uint32_t> nb_cell_;
  std::vector<double> nb_g_;
  std::vector<double> nb_area_m2_;
  std::vector<double> nb_rarea_;
  // Per contact: its normal away from this cell over this cell's conductivity along it, 1/(W/mK) (a
  // lumped contact: its members' mean by area); moving the cell's centroid by d (m) away from the contact
  // adds d·w / area to the contact's resistance (lump, recentre).
  std::vector<Eigen::Vector3f> nb_w_;
  std::vector<Eigen::Vector3d> centroid_mm_;  // per cell (a lumped one: its members' by mass)
  // Per cell: the end of its born neighbours, [first_[i], born_end_[i]) (kept for the born cells and their
  // neighbours at every birth), so the integrator's loops need not test each neighbour.
  std::vector<std::size_t> born_end_;
  std::vector<double> born_g_;        // and the sum of their conductances, W/K
  mutable std::vector<double> loss_;  // per cell, scratch of rhs and jacobian_times
  // Per cell of this rank, at the y of the linear solve under way (jacobian_times_setup).
  std::vector<double> jt_capacity_, jt_loss_derivative_;
  std::size_t born_ = 0;
  std::size_t cap_ = 0;
  // Across ranks (null on one): this rank's cells [lo_, hi_), every rank's block (bounds_) and part of the
  // state (part_counts_: its cells and its share of Q), the halo, and scratch.
  Communicator* comm_ = nullptr;
  std::size_t lo_ = 0, hi_ = 0;
  std::vector<std::size_t> bounds_;
  std::vector<int> part_counts_, send_counts_, recv_counts_;
  std::vector<std::uint32_t> send_cells_, recv_cells_;
  mutable std::vector<double> send_buffer_, recv_buffer_, halo_y_, halo_v_, gathered_;
  std::vector<double> h_;                  // convection coefficient at the cell's height, W/m²K
  double fan_full_h_ = 0.0, fan_h_ = 0.0;  // forced convection with the fan at full and now, W/m²K
  double deposition_c_, ambient_c_, bed_c_, eps_sigma_;
  std::vector<double> birth_c_;  // per cell: its temperature as it is born, °C
  double table_radiant_c_;       // the table as the faces that see it see it: held at bed_c_, or the air's
  double energy_in_J_ = 0.0;
  double rel_tol_ = 1e-4, abs_tol_k_ = 0.01, abs_tol_J_ = 1.0;
};

}  // namespace beadtwin::thermal
