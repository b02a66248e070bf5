#include "thermal/heat.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <span>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.hpp"
#include "core/hash.hpp"
#include "core/units.hpp"
#include "thermal/cvode.hpp"

namespace beadtwin::thermal {
namespace {

constexpr double kM2PerMm2 = 1e-6;
constexpr double kMPerMm = 1e-3;
constexpr double kM3PerMm3 = 1e-9;

// One neighbour of a cell: who, the conductance to it and the contact area that is open surface while the
// neighbour is not yet born.
struct Neighbour {
  std::uint32_t cell = 0;
  double conductance_W_K = 0.0;
  double area_m2 = 0.0;
};

// The conductivity tensor of a cell whose bead runs along `along` (a unit vector in plan).
Eigen::Matrix3d conductivity(const Eigen::Vector2d& along, const Material& m) {
  const Eigen::Vector3d t(along.x(), along.y(), 0.0);
  const Eigen::Vector3d s(-along.y(), along.x(), 0.0);
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  return m.conductivity_along_W_mK * t * t.transpose() + m.conductivity_across_W_mK * s * s.transpose() +
         m.conductivity_through_W_mK * z * z.transpose();
}

// f(i) for every i in [begin, end), on TBB's threads when there are enough to be worth handing out.
template <class F>
void for_range(std::size_t begin, std::size_t end, const F& f) {
  constexpr std::size_t kGrain = 4096;
  if (end < begin + 2 * kGrain) {
    for (std::size_t i = begin; i < end; ++i) f(i);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i) f(i);
                    });
}

// The part as an ODE system: y = [T_0 .. T_{n-1} (°C) | Q (J lost through the boundary)]. Cells are in
// birth order, so the born ones are the first born_.
//
// Across ranks (HeatOptions::communicator) each rank integrates a contiguous block of the cells, [lo_, hi_),
// and its own share of Q: its part of the state is [T_lo .. T_{hi-1} | Q_rank], and the energy lost is the
// sum of the ranks' shares. Cells in birth order are cells by height, so the blocks are slices of the part,
// bottom to top. Each right-hand side and Jacobian product first brings in, from the other ranks, the
// temperatures of the cells its own cells touch (the halo).
class PartModel final : public OdeSystem {
 public:
  PartModel(const ThermalMesh& mesh, const Material& material, const Environment& env)
      : n_(mesh.cells.size()),
        material_(material),
        deposition_c_(material.deposition_temp_c),
        ambient_c_(env.ambient_c),
        ambient_k4_(std::pow(env.ambient_c + kKelvinOffset, 4)),
        bed_c_(env.bed_temp_c),
        eps_sigma_(material.emissivity * kStefanBoltzmann_W_m2K4) {
    mass_kg_.resize(n_);
    exposed_m2_.resize(n_);
    table_W_K_.resize(n_);
    h_.resize(n_);
    for (std::size_t i = 0; i < n_; ++i) {
      const ThermalCell& c = mesh.cells[i];
      h_[i] = env.convection_at(c.centroid_mm.z() - mesh.table_z_mm);
      mass_kg_[i] = material.density_kg_m3 * c.volume_mm3 * kM3PerMm3;
      exposed_m2_[i] = c.open_area_mm2 * kM2PerMm2;
      table_W_K_[i] = env.bed_insulated ? 0.0 : env.bed_contact_W_m2K * c.table_area_mm2 * kM2PerMm2;
    }
    std::vector<std::size_t> count(n_ + 1, 0);
    for (const ThermalLink& l : mesh.links) {
      ++count[l.a + 1];
      ++count[l.b + 1];
    }
    for (std::size_t i = 0; i < n_; ++i) count[i + 1] += count[i];
    first_ = count;
    std::vector<Neighbour> neighbours(count[n_]);
    std::vector<std::size_t> next(count.begin(), count.end() - 1);
    const double half_voxel = 0.5 * mesh.voxel_size_mm;
    for (const ThermalLink& l : mesh.links) {
      const ThermalCell& a = mesh.cells[l.a];
      const ThermalCell& b = mesh.cells[l.b];
      const double area = l.area_mm2();
      const double vector_length = l.area_vector_mm2.norm();
      const Eigen::Vector3d normal =
          vector_length > 0.0 ? Eigen::Vector3d(l.area_vector_mm2 / vector_length) : Eigen::Vector3d::UnitZ();
      const Eigen::Matrix3d k = 0.5 * (conductivity(a.along, material) + conductivity(b.along, material));
      const double k_n = normal.dot(k * normal);
      const double distance = std::max(std::abs((b.centroid_mm - a.centroid_mm).dot(normal)), half_voxel);
      const double g = k_n * area * kM2PerMm2 / (distance * kMPerMm);
      neighbours[next[l.a]++] = {l.b, g, area * kM2PerMm2};
      neighbours[next[l.b]++] = {l.a, g, area * kM2PerMm2};
    }
    // Sorted by neighbour, so the born ones come first; kept as three arrays, so that the integrator's
    // loops read 12 bytes a neighbour (who and the conductance) rather than a whole Neighbour.
    for (std::size_t i = 0; i < n_; ++i)
      std::sort(neighbours.begin() + static_cast<std::ptrdiff_t>(first_[i]),
                neighbours.begin() + static_cast<std::ptrdiff_t>(first_[i + 1]),
                [](const Neighbour& x, const Neighbour& y) { return x.cell < y.cell; });
    nb_cell_.reserve(neighbours.size());
    nb_g_.reserve(neighbours.size());
    nb_area_m2_.reserve(neighbours.size());
    for (const Neighbour& nb : neighbours) {
      nb_cell_.push_back(nb.cell);
      nb_g_.push_back(nb.conductance_W_K);
      nb_area_m2_.push_back(nb.area_m2);
    }
    // Every contact is open surface until the neighbour is born.
    for (std::size_t i = 0; i < n_; ++i)
      for (std::size_t k = first_[i]; k < first_[i + 1]; ++k) exposed_m2_[i] += nb_area_m2_[k];
    loss_.assign(n_, 0.0);
    born_end_.assign(first_.begin(), first_.end() - 1);
    born_g_.assign(n_, 0.0);
  }

  // The integrator's state: the first `capacity` cells (the born ones and room for the next) and the energy
  // lost, at index capacity. Every vector operation of a step runs over it, so it grows with the print.
  // Shares it among the ranks anew (the cells born so far set the blocks).
  void set_capacity(std::size_t capacity) {
    BT_CHECK(capacity >= born_ && capacity <= n_);
    cap_ = capacity;
    partition();
  }
  std::size_t capacity() const { return cap_; }
  void set_communicator(Communicator* comm) { comm_ = comm != nullptr && comm->size() > 1 ? comm : nullptr; }
  Communicator* communicator() const { return comm_; }

  // This rank's part of a state of all cells (the first capacity() and the energy lost): its cells, and the
  // energy lost on rank 0 (0 on the others, so that the ranks' shares add up to it).
  std::vector<double> local(std::span<const double> full) const {
    BT_CHECK_OP(full.size(), ==, cap_ + 1);
    std::vector<double> out(full.begin() + static_cast<std::ptrdiff_t>(lo_),
                            full.begin() + static_cast<std::ptrdiff_t>(hi_));
    out.push_back(comm_ == nullptr || comm_->rank() == 0 ? full[cap_] : 0.0);
    return out;
  }
  // The state of all cells from every rank's part (`local` is this rank's): in `buffer`, or `local` itself
  // on one rank.
  std::span<const double> gather(std::span<const double> local, std::vector<double>& buffer) const {
    if (comm_ == nullptr) return local;
    BT_CHECK_OP(local.size(), ==, hi_ - lo_ + 1);
    gathered_.resize(cap_ + part_counts_.size());
    comm_->all_gather(local, part_counts_, gathered_);
    buffer.resize(cap_ + 1);
    double lost = 0.0;
    std::size_t at = 0;
    for (std::size_t r = 0; r < part_counts_.size(); ++r) {
      const std::size_t cells = bounds_[r + 1] - bounds_[r];
      std::copy_n(gathered_.begin() + static_cast<std::ptrdiff_t>(at), cells,
                  buffer.begin() + static_cast<std::ptrdiff_t>(bounds_[r]));
      lost += gathered_[at + cells];
      at += cells + 1;
    }
    buffer[cap_] = lost;
    return buffer;
  }
  std::size_t born() const { return born_; }
  // C / ΣG of cell i over all its contacts, s.
  double time_constant_s(std::size_t i) const {
    double g = table_W_K_[i];
    for (std::size_t k = first_[i]; k < first_[i + 1]; ++k) g += nb_g_[k];
    return g > 0.0 ? heat_capacity(i, deposition_c_) / g : std::numeric_limits<double>::infinity();
  }

  // Cells [born_, end) are born: at the deposition temperature in y, their faces towards born cells closed.
  void birth(std::size_t end, std::span<double> y) {
    for (std::size_t i = born_; i < end; ++i) {
      y[i] = deposition_c_;
      for (std::size_t k = first_[i]; k < first_[i + 1]; ++k) {
        if (nb_cell_[k] < end) exposed_m2_[i] -= nb_area_m2_[k];
        if (nb_cell_[k] < born_) exposed_m2_[nb_cell_[k]] -= nb_area_m2_[k];
      }
      energy_in_J_ += mass_kg_[i] * material_.enthalpy_J_kg(ambient_c_, deposition_c_);
    }
    const std::size_t before = born_;
    born_ = end;
    for (std::size_t i = before; i < end; ++i) {
      find_born_end(i);
      for (std::size_t k = first_[i]; k < first_[i + 1] && nb_cell_[k] < before; ++k)
        find_born_end(nb_cell_[k]);
    }
  }

  std::size_t size_of_model() const { return n_; }
  double mass_kg(std::size_t i) const { return mass_kg_[i]; }
  // Whether cell i has a neighbour not yet born (neighbours are sorted, so the last tells).
  bool on_top(std::size_t i) const {
    return first_[i] != first_[i + 1] && nb_cell_[first_[i + 1] - 1] >= born_;
  }
  std::span<const std::uint32_t> neighbours(std::size_t i) const {
    return {nb_cell_.data() + first_[i], nb_cell_.data() + first_[i + 1]};
  }

  // Lumps runs of born cells into one cell each (thermal/heat.hpp, settled cells): `to[i]`, for every cell,
  // is its cell afterwards, non-decreasing, equal only within a run, one to one for the cells not yet born.
  // A lumped cell has its members' mass, open and table surface and contacts (summed per neighbour; the
  // contacts between members go); its temperature is the one at which it holds its members' enthalpy, so the
  // energy stored does not change. `y` (the first capacity() cells) becomes the new cells' state; the energy
  // lost, after it, is carried over.
  void lump(std::span<const std::uint32_t> to, std::vector<double>& y) {
    const std::size_t m = n_ == 0 ? 0 : std::size_t{to[n_ - 1]} + 1;
    std::vector<double> mass(m, 0.0), exposed(m, 0.0), table(m, 0.0), h_area(m, 0.0), h_sum(m, 0.0),
        count(m, 0.0), enthalpy(m, 0.0);
    for (std::size_t i = 0; i < n_; ++i) {
      const std::size_t g = to[i];
      mass[g] += mass_kg_[i];
      exposed[g] += exposed_m2_[i];
      table[g] += table_W_K_[i];
      h_area[g] += h_[i] * exposed_m2_[i];
      h_sum[g] += h_[i];
      count[g] += 1.0;
      if (i < cap_) enthalpy[g] += mass_kg_[i] * material_.enthalpy_J_kg(ambient_c_, y[i]);
    }
    std::vector<double> h(m);
    for (std::size_t g = 0; g < m; ++g)
      h[g] = exposed[g] > 0.0 ? h_area[g] / exposed[g] : h_sum[g] / count[g];
    // Contacts: the members' lists, renumbered (still in order, as `to` keeps order), merged per neighbour.
    std::vector<std::size_t> first(m + 1, 0);
    std::vector<std::uint32_t> nb_cell;
    std::vector<double> nb_g, nb_area;
    nb_cell.reserve(nb_cell_.size());
    nb_g.reserve(nb_cell_.size());
    nb_area.reserve(nb_cell_.size());
    std::vector<std::pair<std::uint32_t, std::size_t>> entries;  // (new neighbour, old entry)
    for (std::size_t i = 0; i < n_;) {
      const std::uint32_t g = to[i];
      std::size_t j = i;
      entries.clear();
      for (; j < n_ && to[j] == g; ++j)
        for (std::size_t k = first_[j]; k < first_[j + 1]; ++k)
          if (to[nb_cell_[k]] != g) entries.emplace_back(to[nb_cell_[k]], k);
      std::sort(entries.begin(), entries.end());
      for (std::size_t e = 0; e < entries.size(); ++e) {
        if (e == 0 || entries[e].first != entries[e - 1].first) {
          nb_cell.push_back(entries[e].first);
          nb_g.push_back(0.0);
          nb_area.push_back(0.0);
        }
        nb_g.back() += nb_g_[entries[e].second];
        nb_area.back() += nb_area_m2_[entries[e].second];
      }
      first[g + 1] = nb_cell.size();
      i = j;
    }
    // The state: each new cell at the temperature that holds its enthalpy (Newton on m h(T) = H from the
    // mass-weighted mean; c_p changes slowly with T, so a few steps reach round-off).
    const std::size_t cap = cap_ == 0 ? 0 : std::size_t{to[cap_ - 1]} + 1;
    std::vector<double> state(cap + 1, 0.0), weighted(cap, 0.0);
    for (std::size_t i = 0; i < cap_; ++i) weighted[to[i]] += mass_kg_[i] * y[i];
    for (std::size_t g = 0; g < cap; ++g) {
      double t = weighted[g] / mass[g];
      for (int it = 0; it < 8; ++it) {
        const double f = mass[g] * material_.enthalpy_J_kg(ambient_c_, t) - enthalpy[g];
        const double step = f / (mass[g] * material_.specific_heat_at(t));
        t -= step;
        if (std::abs(step) < 1e-9) break;
      }
      state[g] = t;
    }
    state[cap] = y[cap_];
    const std::size_t born = born_ == 0 ? 0 : std::size_t{to[born_ - 1]} + 1;
    n_ = m;
    mass_kg_ = std::move(mass);
    exposed_m2_ = std::move(exposed);
    table_W_K_ = std::move(table);
    h_ = std::move(h);
    first_ = std::move(first);
    nb_cell_ = std::move(nb_cell);
    nb_g_ = std::move(nb_g);
    nb_area_m2_ = std::move(nb_area);
    loss_.assign(n_, 0.0);
    born_ = born;
    born_end_.resize(n_);
    born_g_.resize(n_);
    for (std::size_t i = 0; i < n_; ++i) find_born_end(i);
    cap_ = cap;
    y = std::move(state);
  }

  double energy_in_J() const { return energy_in_J_; }
  double energy_stored_J(std::span<const double> y) const {
    double e = 0.0;
    for (std::size_t i = 0; i < born_; ++i) e += mass_kg_[i] * material_.enthalpy_J_kg(ambient_c_, y[i]);
    return e;
  }

  void set_tolerances(double rel_tol, double abs_tol_k) {
    rel_tol_ = rel_tol;
    abs_tol_k_ = abs_tol_k;
    double total = 0.0;
    for (std::size_t i = 0; i < n_; ++i) total += heat_capacity(i, deposition_c_);
    abs_tol_J_ = std::max(total * abs_tol_k, 1e-12);
  }

  // dT/dt of born cell i in state y (indexed by cell), K/s; its boundary loss, W, in `loss`.
  double rate(std::size_t i, const double* y, double& loss) const {
    const double t = y[i];
    double flux = 0.0;
    for (std::size_t k = first_[i], e = born_end_[i]; k < e; ++k) flux += nb_g_[k] * (y[nb_cell_[k]] - t);
    const double tk = t + kKelvinOffset;
    loss = exposed_m2_[i] * (h_[i] * (t - ambient_c_) + eps_sigma_ * (tk * tk * tk * tk - ambient_k4_)) +
           table_W_K_[i] * (t - bed_c_);
    return (flux - loss) / heat_capacity(i, t);
  }

  // The vectors below are this rank's part of the state: cell i at [i − lo_], its share of Q last.
  void rhs(double /*t*/, std::span<const double> y, std::span<double> ydot) override {
    const double* all = with_halo(y, halo_y_);
    const std::size_t end = owned_born();
    for_cells(lo_, end, [&](std::size_t i) { ydot[i - lo_] = rate(i, all, loss_[i]); });
    double q = 0.0;
    for (std::size_t i = lo_; i < end; ++i) q += loss_[i];
    for (std::size_t i = end; i < hi_; ++i) ydot[i - lo_] = 0.0;
    ydot[hi_ - lo_] = q;
  }

  // What every product of a linear solve shares: each cell's heat capacity and boundary loss derivative at
  // the solve's y (CVODE calls this before each solve: cvode.hpp). Kept as they are, not as reciprocals,
  // so a product is the same to the last bit as one working them out itself.
  void jacobian_times_setup(double /*t*/, std::span<const double> y) override {
    const std::size_t end = owned_born();
    jt_capacity_.resize(hi_ - lo_);
    jt_loss_derivative_.resize(hi_ - lo_);
    for_cells(lo_, end, [&](std::size_t i) {
      const double yi = y[i - lo_];
      jt_capacity_[i - lo_] = heat_capacity(i, yi);
      jt_loss_derivative_[i - lo_] = loss_derivative(i, yi);
    });
  }

  void jacobian_times(double /*t*/, std::span<const double> /*y*/, std::span<const double> v,
                      std::span<double> jv) override {
    const std::size_t end = owned_born();
    const double* all_v = with_halo(v, halo_v_);
    BT_CHECK_OP(jt_capacity_.size(), ==, hi_ - lo_);
    for_cells(lo_, end, [&](std::size_t i) {
      double sum = 0.0;
      const double vi = all_v[i];
      for (std::size_t k = first_[i], e = born_end_[i]; k < e; ++k)
        sum += nb_g_[k] * (all_v[nb_cell_[k]] - vi);
      const double d_loss = jt_loss_derivative_[i - lo_] * vi;
      loss_[i] = d_loss;
      jv[i - lo_] = (sum - d_loss) / jt_capacity_[i - lo_];
    });
    double q = 0.0;
    for (std::size_t i = lo_; i < end; ++i) q += loss_[i];
    for (std::size_t i = end; i < hi_; ++i) jv[i - lo_] = 0.0;
    jv[hi_ - lo_] = q;
  }

  void jacobian_diagonal(double /*t*/, std::span<const double> y, std::span<double> diagonal) override {
    const std::size_t end = owned_born();
    for_cells(lo_, end, [&](std::size_t i) {
      diagonal[i - lo_] = -(born_g_[i] + loss_derivative(i, y[i - lo_])) / heat_capacity(i, y[i - lo_]);
    });
    for (std::size_t i = end; i < hi_; ++i) diagonal[i - lo_] = 0.0;
    diagonal[hi_ - lo_] = 0.0;
  }

  void error_weights(std::span<const double> y, std::span<double> weights) override {
    const std::size_t cells = hi_ - lo_;
    for (std::size_t i = 0; i < cells; ++i) weights[i] = 1.0 / (rel_tol_ * std::abs(y[i]) + abs_tol_k_);
    weights[cells] = 1.0 / (rel_tol_ * std::abs(y[cells]) + abs_tol_J_);
  }

 private:
  // m c_p(T) of cell i, J/K. (The Jacobian leaves out the change of c_p with T: Newton's matrix need not
  // be exact.)
  double heat_capacity(std::size_t i, double t) const { return mass_kg_[i] * material_.specific_heat_at(t); }

  // d(loss)/dT of cell i at temperature t, W/K.
  double loss_derivative(std::size_t i, double t) const {
    const double tk = t + kKelvinOffset;
    return exposed_m2_[i] * (h_[i] + 4.0 * eps_sigma_ * tk * tk * tk) + table_W_K_[i];
  }

  void find_born_end(std::size_t i) {
    double g = 0.0;
    std::size_t k = first_[i];
    for (; k < first_[i + 1] && nb_cell_[k] < born_; ++k) g += nb_g_[k];
    born_end_[i] = k;
    born_g_[i] = g;
  }

  // The end of this rank's born cells: [lo_, owned_born()).
  std::size_t owned_born() const { return std::clamp(born_, lo_, hi_); }

  // The blocks of the ranks: rank r integrates cells [bounds_[r], bounds_[r + 1]). Between two rebuilds of
  // the integrator the born cells grow from born_ towards cap_, so the blocks share out the cells born on
  // average over that time, (born_ + cap_) / 2, and the last block takes the rest. With several ranks, also
  // the halo: which of its cells each rank sends to which, and which it receives.
  void partition() {
    const std::size_t ranks = comm_ != nullptr ? static_cast<std::size_t>(comm_->size()) : 1;
    const std::size_t me = comm_ != nullptr ? static_cast<std::size_t>(comm_->rank()) : 0;
    bounds_.assign(ranks + 1, cap_);
    bounds_[0] = 0;
    const double expected = 0.5 * static_cast<double>(born_ + cap_);
    for (std::size_t r = 1; r < ranks; ++r)
      bounds_[r] = std::min(cap_, static_cast<std::size_t>(std::llround(expected * static_cast<double>(r) /
                                                                        static_cast<double>(ranks))));
    lo_ = bounds_[me];
    hi_ = bounds_[me + 1];
    if (comm_ == nullptr) return;
    part_counts_.resize(ranks);
    for (std::size_t r = 0; r < ranks; ++r)
      part_counts_[r] = static_cast<int>(bounds_[r + 1] - bounds_[r] + 1);
    // The cells outside rank r's block that its cells touch, in order (each rank works this out for all).
    const auto owner = [&](std::uint32_t j) {
      return static_cast<std::size_t>(std::upper_bound(bounds_.begin(), bounds_.end(), std::size_t{j}) -
                                      bounds_.begin()) -
             1;
    };
    std::vector<std::uint32_t> needs;
    const auto needed_by = [&](std::size_t r) {
      needs.clear();
      for (std::size_t i = bounds_[r]; i < bounds_[r + 1]; ++i)
        for (std::size_t k = first_[i]; k < first_[i + 1] && nb_cell_[k] < cap_; ++k)
          if (nb_cell_[k] < bounds_[r] || nb_cell_[k] >= bounds_[r + 1]) needs.push_back(nb_cell_[k]);
      std::sort(needs.begin(), needs.end());
      needs.erase(std::unique(needs.begin(), needs.end()), needs.end());
    };
    send_counts_.assign(ranks, 0);
    recv_counts_.assign(ranks, 0);
    send_cells_.clear();
    for (std::size_t r = 0; r < ranks; ++r) {
      needed_by(r);
      if (r == me) {
        recv_cells_ = needs;
        for (const std::uint32_t j : needs) ++recv_counts_[owner(j)];
        continue;
      }
      for (const std::uint32_t j : needs)
        if (j >= lo_ && j < hi_) send_cells_.push_back(j), ++send_counts_[r];
    }
    send_buffer_.resize(send_cells_.size());
    recv_buffer_.resize(recv_cells_.size());
  }

  // Values of a vector by cell for this rank's cells and its halo: `local` itself on one rank; else `all`,
  // its block copied in and the halo brought from the other ranks.
  const double* with_halo(std::span<const double> local, std::vector<double>& all) const {
    if (comm_ == nullptr) return local.data();
    all.resize(cap_);
    std::copy(local.begin(), local.begin() + static_cast<std::ptrdiff_t>(hi_ - lo_),
              all.begin() + static_cast<std::ptrdiff_t>(lo_));
    for (std::size_t k = 0; k < send_cells_.size(); ++k) send_buffer_[k] = local[send_cells_[k] - lo_];
    comm_->exchange(send_buffer_, send_counts_, recv_buffer_, recv_counts_);
    for (std::size_t k = 0; k < recv_cells_.size(); ++k) all[recv_cells_[k]] = recv_buffer_[k];
    return all.data();
  }

  template <class F>
  void for_cells(std::size_t begin, std::size_t end, const F& f) const {
    for_range(begin, end, f);
  }

  std::size_t n_;
  std::vector<double> mass_kg_;
  Material material_;
  std::vector<double> exposed_m2_;  // open now: for good, and towards neighbours not yet born
  std::vector<double> table_W_K_;   // bed contact conductance
  std::vector<std::size_t> first_;
  // Neighbours of cell i at [first_[i], first_[i + 1]), by index: who, the conductance, the contact area.
  std::vector<std::uint32_t> nb_cell_;
  std::vector<double> nb_g_;
  std::vector<double> nb_area_m2_;
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
  std::vector<double> h_;  // convection coefficient at the cell's height, W/m²K
  double deposition_c_, ambient_c_, ambient_k4_, bed_c_, eps_sigma_;
  double energy_in_J_ = 0.0;
  double rel_tol_ = 1e-4, abs_tol_k_ = 0.01, abs_tol_J_ = 1.0;
};

// The median of value(i) over cells [0, n), n > 0.
template <class F>
double median_over_cells(std::size_t n, const F& value) {
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = value(i);
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n / 2), v.end());
  return v[n / 2];
}

// Across ranks, every rank must solve the same part and options, or their messages would not match: each
// compares a fingerprint of what it was given (FNV-1a over the cells' births, volumes and the links, and the
// options the integration depends on) with rank 0's.
void check_same_on_every_rank(const ThermalMesh& mesh, const HeatOptions& o, Communicator& ranks) {
  Fnv1a h;
  const auto mix = [&h](const auto& value) { h.add_value(value); };
  mix(mesh.cells.size());
  mix(mesh.links.size());
  for (const ThermalCell& c : mesh.cells) mix(c.birth_s), mix(c.volume_mm3), mix(c.open_area_mm2);
  for (const ThermalLink& l : mesh.links) mix(l.a), mix(l.b), mix(l.interface);
  mix(o.rel_tol), mix(o.abs_tol_k), mix(o.birth_interval_s), mix(o.cooldown_s), mix(o.lump);
  const double mine = static_cast<double>(h.value() >> 12);  // 52 bits: exact in a double
  if (ranks.gather_each(mine)[0] != mine)
    throw InternalError(
        fmt::format("thermal solve across ranks: rank {} was given another part than rank 0", ranks.rank()));
}

void check_options(const HeatOptions& o) {
  const auto positive = [](double v) { return v > 0.0 && std::isfinite(v); };
  if (!positive(o.rel_tol))
    throw InputError({}, "thermal.rel_tol", fmt::format("must be > 0, got {}", o.rel_tol));
  if (!positive(o.abs_tol_k))
    throw InputError({}, "thermal.abs_tol", fmt::format("must be > 0, got {}", o.abs_tol_k));
  if (!(o.birth_interval_s >= 0.0) || !std::isfinite(o.birth_interval_s))
    throw InputError({}, "thermal.birth_interval",
                     fmt::format("must be 0 or more, got {}", o.birth_interval_s));
  if (!(o.cooldown_s >= 0.0) || !std::isfinite(o.cooldown_s))
    throw InputError({}, "thermal.cooldown", fmt::format("must be 0 or more, got {}", o.cooldown_s));
  if (!positive(o.sample_interval_s))
    throw InputError({}, "thermal.sample_interval", fmt::format("must be > 0, got {}", o.sample_interval_s));
  if (o.lump_depth < 1 || o.lump_depth > 100)
    throw InputError({}, "thermal.lump_depth", fmt::format("must be 1..100, got {}", o.lump_depth));
  if (!(o.lump_tolerance_k >= 0.0) || !std::isfinite(o.lump_tolerance_k))
    throw InputError({}, "thermal.lump_tolerance",
                     fmt::format("must be 0 or more, got {}", o.lump_tolerance_k));
  if (o.krylov_dimension < 1 || o.krylov_dimension > 200)
    throw InputError({}, "thermal.krylov_dimension",
                     fmt::format("must be 1..200, got {}", o.krylov_dimension));
}

}  // namespace

HeatResult solve_heat(const ThermalMesh& mesh, std::size_t layer_count, double end_s,
                      const Material& material, const Environment& env, const HeatOptions& options) {
  check_options(options);
  HeatResult result;
  const std::size_t n = mesh.cells.size();
  if (n == 0) return result;
  if (options.communicator != nullptr && options.communicator->size() > 1)
    check_same_on_every_rank(mesh, options, *options.communicator);
  PartModel model(mesh, material, env);
  model.set_tolerances(options.rel_tol, options.abs_tol_k);
  model.set_communicator(options.communicator);

  // The cells' median conduction time constant sets the birth interval and the longest step.
  double median_tau = median_over_cells(n, [&](std::size_t i) { return model.time_constant_s(i); });
  if (!std::isfinite(median_tau)) median_tau = 5.0;
  // The birth interval and the groups of cells born together.
  result.automatic_interval_s = 0.2 * median_tau;
  double interval = options.birth_interval_s > 0.0 ? options.birth_interval_s : result.automatic_interval_s;
  if (options.birth_interval_s <= 0.0) {  // at most about max_automatic_birth_events: each group spans one
    const double span = mesh.cells.back().birth_s - mesh.cells.front().birth_s;
    interval = std::max(
        interval, span / static_cast<double>(std::max<std::size_t>(options.max_automatic_birth_events, 1)));
    if (interval > result.automatic_interval_s)
      result.notes.push_back(fmt::format(
          "thermal birth interval {:.3g} s instead of {:.3g} s (a fifth of the cells' median time constant), "
          "so that the print's cells are born in at most about {} events; set thermal.birth_interval to "
          "choose",
          interval, result.automatic_interval_s, options.max_automatic_birth_events));
  }
  result.birth_interval_s = interval;
  struct Group {
    std::size_t end = 0;  // cells [previous end, end)
    double time_s = 0.0;
  };
  std::vector<Group> groups;
  for (std::size_t i = 0; i < n;) {
    const double first = mesh.cells[i].birth_s;
    std::size_t j = i;
    while (j < n && mesh.cells[j].birth_s <= first + interval) ++j;
    groups.push_back({j, 0.5 * (first + mesh.cells[j - 1].birth_s)});
    i = j;
  }
  result.birth_events = groups.size();

  // Interfaces, by the younger cell (each group opens its own).
  std::vector<std::vector<std::size_t>> by_younger(n);
  for (std::size_t l = 0; l < mesh.links.size(); ++l) {
    const ThermalLink& link = mesh.links[l];
    if (!link.interface) continue;
    InterfaceResult r;
    r.older = link.a;
    r.younger = link.b;
    r.area_mm2 = link.area_mm2();
    const double length = link.area_vector_mm2.norm();
    r.on_top = length > 0.0 && std::abs(link.area_vector_mm2.z()) >= 0.5 * length;
    by_younger[link.b].push_back(result.interfaces.size());
    result.interfaces.push_back(r);
  }

  // The model's cells: the mesh's cells until some are lumped (settled cells, below), after which
  // model_of[i] is mesh cell i's model cell (non-decreasing; model_of[n] is the model's cell count).
  // Everything the integrator reads per step is kept by model cell and rebuilt at each lumping.
  std::vector<std::uint32_t> model_of(n + 1);
  for (std::size_t i = 0; i <= n; ++i) model_of[i] = static_cast<std::uint32_t>(i);
  std::size_t mesh_born = 0;  // mesh cells born so far: [0, mesh_born)

  // Interfaces by both model cells (the healing integral is advanced only where a cell is warm enough to
  // heal), flat, each entry with the interface's cells beside it: the scan for healing interfaces after every
  // step reads memory in order rather than chasing per-cell lists and interface records (that was most of its
  // time). An interface inside one lumped cell is not listed: its two sides are at the lumped cell's
  // temperature, so it heals at the lumped cell's rate, integrated once per lumped cell (lump_integral) and
  // handed to each of its inner interfaces when the cell is lumped again or at the end.
  struct CellInterface {
    std::uint32_t interface, other, younger;
  };
  std::vector<std::size_t> cell_first;
  std::vector<CellInterface> cell_interfaces;
  // Each interface's two model cells, packed: the healing rate reads them for every healing interface twice a
  // step, and from the interface records (64 bytes each) the default scenario's thermal stage took 0.3 s
  // longer.
  std::vector<std::array<std::uint32_t, 2>> cells_of(result.interfaces.size());
  std::vector<std::size_t> inner_first;  // model cell g's inner interfaces: [inner_first[g], [g + 1])
  std::vector<std::uint32_t> inner;      // interfaces
  std::vector<double> lump_integral;     // per model cell: ∫ dt / t_w at its temperature since lumped
  std::vector<double> integral(result.interfaces.size(), 0.0);  // ∫ dt / t_w so far
  // The layers' share of each model cell, for the history: (layer, volume), by model cell.
  std::vector<std::size_t> part_first;
  std::vector<std::pair<std::uint32_t, double>> parts;
  const auto index_model = [&] {
    const std::size_t m = model_of[n];
    cell_first.assign(m + 1, 0);
    inner_first.assign(m + 1, 0);
    for (std::size_t k = 0; k < result.interfaces.size(); ++k) {
      const std::uint32_t a = model_of[result.interfaces[k].older],
                          b = model_of[result.interfaces[k].younger];
      cells_of[k] = {a, b};
      if (a == b) {
        ++inner_first[a + 1];
      } else {
        ++cell_first[a + 1];
        ++cell_first[b + 1];
      }
    }
    for (std::size_t g = 0; g < m; ++g)
      cell_first[g + 1] += cell_first[g], inner_first[g + 1] += inner_first[g];
    cell_interfaces.resize(cell_first[m]);
    inner.resize(inner_first[m]);
    std::vector<std::size_t> next(cell_first.begin(), cell_first.end() - 1);
    std::vector<std::size_t> next_inner(inner_first.begin(), inner_first.end() - 1);
    for (std::uint32_t k = 0; k < result.interfaces.size(); ++k) {
      const auto [a, b] = cells_of[k];
      if (a == b) {
        inner[next_inner[a]++] = k;
        continue;
      }
      cell_interfaces[next[a]++] = {k, b, b};
      cell_interfaces[next[b]++] = {k, a, b};
    }
    lump_integral.assign(m, 0.0);
    part_first.assign(m + 1, 0);
    parts.clear();
    std::uint32_t last = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const int layer = mesh.cells[i].layer;
      if (layer < 0 || static_cast<std::size_t>(layer) >= layer_count) continue;
      const std::uint32_t g = model_of[i];
      // A model cell's mesh cells are consecutive: its entries of one layer (most have one) are merged.
      if (!parts.empty() && last == g && parts.back().first == static_cast<std::uint32_t>(layer)) {
        parts.back().second += mesh.cells[i].volume_mm3;
      } else {
        parts.emplace_back(static_cast<std::uint32_t>(layer), mesh.cells[i].volume_mm3);
        ++part_first[g + 1];
      }
      last = g;
    }
    for (std::size_t g = 0; g < m; ++g) part_first[g + 1] += part_first[g];
  };
  // Hands each lumped cell's healing to its inner interfaces.
  const auto flush_lumps = [&] {
    for (std::size_t g = 0; g + 1 < inner_first.size(); ++g)
      for (std::size_t e = inner_first[g]; e < inner_first[g + 1]; ++e)
        integral[inner[e]] += lump_integral[g];
    std::fill(lump_integral.begin(), lump_integral.end(), 0.0);
  };
  index_model();

  const Reptation reptation(material);
  // A cell is warm when it may be above the healing threshold during a step: at either end (with a margin
  // for what the interpolant does between them). An interface heals only while one of its cells is warm.
  const double warm_c = reptation.min_temp_c() - 1.0;
  std::vector<char> warm(n, 0);
  std::vector<std::uint32_t> healing_now, lumps_healing_now;

  // History samples.
  const double t0 = groups.front().time_s;
  const double t_end = std::max(groups.back().time_s, end_s) + options.cooldown_s;
  result.start_time_s = t0;
  result.end_time_s = t_end;
  result.layer_temp_c.assign(layer_count, {});
  double next_sample = t0;
  // (time, index of the request), in time order.
  std::vector<std::pair<double, std::size_t>> snapshot_times;
  for (std::size_t k = 0; k < options.snapshot_times_s.size(); ++k)
    snapshot_times.emplace_back(std::clamp(options.snapshot_times_s[k], t0, t_end), k);
  std::sort(snapshot_times.begin(), snapshot_times.end());
  std::size_t next_snapshot = 0;
  const auto snapshot = [&](double t, std::size_t request, std::span<const double> y) {
    TemperatureSnapshot s;
    s.time_s = t;
    s.request = request;
    s.temp_c.assign(n, std::numeric_limits<float>::quiet_NaN());
    for (std::size_t i = 0; i < mesh_born; ++i) s.temp_c[i] = static_cast<float>(y[model_of[i]]);
    result.snapshots.push_back(std::move(s));
  };
  std::vector<double> layer_sum(layer_count), layer_volume(layer_count);
  const auto sample = [&](double t, std::span<const double> y) {
    std::fill(layer_sum.begin(), layer_sum.end(), 0.0);
    std::fill(layer_volume.begin(), layer_volume.end(), 0.0);
    for (std::size_t g = 0; g < model.born(); ++g)
      for (std::size_t e = part_first[g]; e < part_first[g + 1]; ++e) {
        layer_sum[parts[e].first] += parts[e].second * y[g];
        layer_volume[parts[e].first] += parts[e].second;
      }
    result.sample_times_s.push_back(t);
    for (std::size_t k = 0; k < layer_count; ++k)
      result.layer_temp_c[k].push_back(layer_volume[k] > 0.0
                                           ? static_cast<float>(layer_sum[k] / layer_volume[k])
                                           : std::numeric_limits<float>::quiet_NaN());
  };

  // The integrator's state (PartModel::set_capacity) at the end of the last step; and every model cell's
  // temperature for the cells beyond it (unborn: they wait at the deposition temperature).
  std::vector<double> temps(n, material.deposition_temp_c);
  std::size_t cap = std::min(n, std::max<std::size_t>(groups.front().end, 1024));
  std::vector<double> before(temps.begin(), temps.begin() + static_cast<std::ptrdiff_t>(cap));
  before.push_back(0.0);  // energy lost
  const auto born_group = [&](const Group& g, std::span<double> state) {
    for (std::size_t i = mesh_born; i < g.end; ++i)
      for (const std::size_t k : by_younger[i]) {
        InterfaceResult& r = result.interfaces[k];
        r.substrate_c = material.deposition_temp_c;
        if (r.older < mesh_born) {
          double loss = 0.0;
          r.substrate_c = state[model_of[r.older]];
          r.substrate_rate_K_s = model.rate(model_of[r.older], state.data(), loss);
        }
      }
    model.birth(model_of[g.end], state);
    mesh_born = g.end;
  };
  born_group(groups.front(), before);
  model.set_capacity(cap);

  // Settled cells (HeatOptions::lump): lumped where they are far enough below the top and even enough in
  // temperature that one temperature stands for the run. Checked when enough cells have been born since.
  const double median_mass = median_over_cells(n, [&](std::size_t i) { return model.mass_kg(i); });
  std::size_t born_at_check = 0;
  // Lumps the settled cells in `state` (the first `cap` model cells and the energy lost); true if any were.
  const auto lump_settled = [&](std::vector<double>& state) {
    const std::size_t born = model.born();
    if (mesh_born < born_at_check + std::max(options.lump_check_cells, born / 4)) return false;
    born_at_check = mesh_born;
    // Distance in contacts from the top (cells with a neighbour not yet born), up to lump_depth.
    constexpr std::uint8_t kFar = 255;
    std::vector<std::uint8_t> depth(born, kFar);
    std::vector<std::uint32_t> front, next_front;
    for (std::size_t i = 0; i < born; ++i)
      if (model.on_top(i)) depth[i] = 0, front.push_back(static_cast<std::uint32_t>(i));
    for (int d = 1; d <= options.lump_depth && !front.empty(); ++d) {
      next_front.clear();
      for (const std::uint32_t i : front)
        for (const std::uint32_t j : model.neighbours(i))
          if (j < born && depth[j] == kFar) depth[j] = static_cast<std::uint8_t>(d), next_front.push_back(j);
      std::swap(front, next_front);
    }
    // Runs of consecutive settled cells, each touching the run before it, within lump_tolerance_k of one
    // another and of at most lump_max_cells median cells' mass.
    const std::size_t m = model.size_of_model();
    std::vector<std::uint32_t> to(m);
    std::uint32_t g = 0;
    std::size_t i = 0;
    while (i < m) {
      std::size_t j = i + 1;
      if (i < born && depth[i] == kFar) {
        double lo = state[i], hi = state[i], mass = model.mass_kg(i);
        for (; j < born && depth[j] == kFar; ++j) {
          const double t = state[j];
          if (std::max(hi, t) - std::min(lo, t) > options.lump_tolerance_k) break;
          if (mass + model.mass_kg(j) > options.lump_max_cells * median_mass) break;
          const auto nb = model.neighbours(j);
          const auto it = std::lower_bound(nb.begin(), nb.end(), static_cast<std::uint32_t>(i));
          if (it == nb.end() || *it >= j) break;  // does not touch the run
          lo = std::min(lo, t), hi = std::max(hi, t), mass += model.mass_kg(j);
        }
      }
      for (std::size_t k = i; k < j; ++k) to[k] = g;
      ++g;
      i = j;
    }
    if (m - g < std::max<std::size_t>(64, born / 16)) return false;  // too few to be worth a restart
    flush_lumps();
    model.lump(to, state);
    for (std::uint32_t& c : model_of) c = c < m ? to[c] : g;
    temps.assign(model_of[n], material.deposition_temp_c);
    warm.assign(model_of[n], 0);
    cap = model.capacity();
    index_model();
    ++result.lump_events;
    return true;
  };

  CvodeOptions co;
  co.solver = LinearSolver::kGmres;
  co.krylov_dimension = options.krylov_dimension;
  // No step longer than a few cell time constants. GMRES with a diagonal preconditioner carries a
  // correction a few cells per iteration; over a step of many time constants (a long pause, the cooldown
  // towards steady state) a temperature depends on cells far away, GMRES stops short of it, and the Newton
  // test, which sees only small corrections, passes a state kelvins off. A steady bar of 50 cells ends
  // 1e-3 of its temperature drop off its own network with no limit, 2e-5 with this one (heat_test).
  co.max_step_s = 4.0 * median_tau;
  co.communicator = model.communicator();
  auto cvode = std::make_unique<Cvode>(model, t0, model.local(before), co);
  long steps = 0, rhs = 0, linear = 0;  // of the integrators replaced
  double t = t0;
  std::vector<double> now_all, between_all;  // across ranks: the whole state gathered
  std::vector<double> first_point;           // the state at the first Gauss-Legendre point of a step
  const auto healing_rate = [&](std::span<const double> state, std::uint32_t k) {
    return reptation.rate_per_s(0.5 * (state[cells_of[k][0]] + state[cells_of[k][1]]));
  };
  // The interfaces that heal over the step now ending: born (both cells) and with a warm cell; each once.
  // The integral goes on past 1 (full healing): how far past says how much colder the interface could be.
  // And the lumped cells warm enough for their inner interfaces to heal.
  const auto find_healing = [&](std::span<const double> start, std::span<const double> end) {
    const std::size_t born = model.born();
    for (std::size_t i = 0; i < born; ++i) warm[i] = std::max(start[i], end[i]) >= warm_c;
    healing_now.clear();
    lumps_healing_now.clear();
    for (std::size_t i = 0; i < born; ++i) {
      if (!warm[i]) continue;
      if (inner_first[i] != inner_first[i + 1]) lumps_healing_now.push_back(static_cast<std::uint32_t>(i));
      for (std::size_t e = cell_first[i]; e < cell_first[i + 1]; ++e) {
        const CellInterface& c = cell_interfaces[e];
        if (c.younger >= born) continue;
        if (c.other < i && warm[c.other]) continue;  // counted from the other cell
        healing_now.push_back(c.interface);
      }
    }
  };
  // Integrates to `target`: the healing over each step, and the samples in it.
  const auto advance = [&](double target) {
    if (target <= t) return;
    cvode->set_stop_time(target);
    while (t < target) {
      const double t_prev = t;
      t = cvode->step(target);
      const double half = 0.5 * (t - t_prev);
      const double mid = t_prev + half;
      const double offset = half / std::sqrt(3.0);
      // Across ranks, every rank gathers the whole state: what follows is the same on all of them.
      const std::span<const double> now = model.gather(cvode->state(), now_all);
      find_healing(before, now);
      if (!healing_now.empty() || !lumps_healing_now.empty()) {
        // Gauss-Legendre, two points: exact for cubics in t, as CVODE's interpolant is at low order. Each
        // interface and lumped cell is listed once, so they are shared out among threads as they are (an
        // exponential each, twice a step: a sixth of the stage when it ran on one thread), each summing its
        // two points in order as before.
        const std::span<const double> y0 = model.gather(cvode->interpolate(mid - offset), between_all);
        first_point.assign(y0.begin(), y0.end());
        const std::span<const double> y1 = model.gather(cvode->interpolate(mid + offset), between_all);
        for_range(0, healing_now.size(), [&](std::size_t e) {
          const std::uint32_t k = healing_now[e];
          integral[k] += half * healing_rate(first_point, k);
          integral[k] += half * healing_rate(y1, k);
        });
        for (const std::uint32_t g : lumps_healing_now) {
          lump_integral[g] += half * reptation.rate_per_s(first_point[g]);
          lump_integral[g] += half * reptation.rate_per_s(y1[g]);
        }
      }
      std::copy(now.begin(), now.end(), before.begin());
      while (next_snapshot < snapshot_times.size() && snapshot_times[next_snapshot].first <= t) {
        const auto [ts, request] = snapshot_times[next_snapshot++];
        snapshot(ts, request, ts == t ? now : model.gather(cvode->interpolate(ts), between_all));
      }
      while (next_sample <= t) {
        sample(next_sample,
               next_sample == t ? now : model.gather(cvode->interpolate(next_sample), between_all));
        next_sample += options.sample_interval_s;
      }
    }
  };
  for (std::size_t g = 1; g < groups.size(); ++g) {
    advance(groups[g].time_s);
    const bool lumped = options.lump && lump_settled(before);
    const bool grow = model_of[groups[g].end] > cap;
    if (grow) {  // by half at least, so the integrator is rebuilt a few dozen times in all
      const double lost = before[cap];
      std::copy(before.begin(), before.end() - 1, temps.begin());
      cap = std::min<std::size_t>(model_of[n], std::max<std::size_t>(model_of[groups[g].end], cap + cap / 2));
      before.assign(temps.begin(), temps.begin() + static_cast<std::ptrdiff_t>(cap));
      before.push_back(lost);
    }
    born_group(groups[g], before);
    if (grow || lumped) {
      steps += cvode->steps();
      rhs += cvode->rhs_evaluations();
      linear += cvode->linear_iterations();
      cvode.reset();
      model.set_capacity(cap);
      cvode = std::make_unique<Cvode>(model, t, model.local(before), co);
    }
    // The first step tries to reach the next group at once: the temperatures move slowly against the birth
    // interval (it is a fifth of a cell's time constant), so CVODE usually takes it.
    const double gap = g + 1 < groups.size() ? groups[g + 1].time_s - t : interval;
    cvode->reinit(t, model.local(before), std::max(gap, 1e-3 * interval));
    if (options.progress) options.progress((t - t0) / std::max(t_end - t0, 1e-9));
  }
  advance(t_end);
  if (options.progress) options.progress(1.0);
  flush_lumps();
  for (std::size_t k = 0; k < integral.size(); ++k) {
    result.interfaces[k].healing_integral = integral[k];
    result.interfaces[k].healing = std::min(1.0, std::pow(integral[k], 0.25));
  }
  for (InterfaceResult& r : result.interfaces)
    r.verdict = judge_interface(r.substrate_c, r.on_top, r.healing, material);

  std::copy(before.begin(), before.end() - 1, temps.begin());
  result.final_temp_c.resize(n);
  for (std::size_t i = 0; i < n; ++i) result.final_temp_c[i] = static_cast<float>(temps[model_of[i]]);
  for (std::size_t c = 0; c < n; ++c)  // mesh cells sharing their model cell
    result.lumped_cells += (c > 0 && model_of[c] == model_of[c - 1]) || model_of[c + 1] == model_of[c];
  result.model_cells = model_of[n];
  if (result.lumped_cells > 0)
    result.notes.push_back(fmt::format(
        "thermal: {} of {} cells lumped once settled ({} or more contacts below the top, within {:g} K of "
        "their neighbours along the bead), {} cells at the end; set thermal.lump: false to keep every cell",
        result.lumped_cells, n, options.lump_depth + 1, options.lump_tolerance_k, result.model_cells));
  result.energy_in_J = model.energy_in_J();
  result.energy_lost_J = before[cap];
  result.energy_stored_J = model.energy_stored_J(temps);
  const double scale = std::max(std::abs(result.energy_in_J),
                                std::abs(result.energy_lost_J) + std::abs(result.energy_stored_J));
  result.energy_balance_rel_error =
      scale > 0.0 ? std::abs(result.energy_in_J - result.energy_lost_J - result.energy_stored_J) / scale
                  : 0.0;
  result.ranks = model.communicator() != nullptr ? model.communicator()->size() : 1;
  result.steps = steps + cvode->steps();
  result.rhs_evaluations = rhs + cvode->rhs_evaluations();
  result.linear_iterations = linear + cvode->linear_iterations();
  return result;
}

}  // namespace beadtwin::thermal
