#include "thermal/part_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "core/error.hpp"
#include "thermal/for_range.hpp"

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
  double rarea = 0.0;  // area × this cell's half-cell resistance to the contact, m²·m²K/W
  Eigen::Vector3f w = Eigen::Vector3f::Zero();  // PartModel::nb_w_
};

// A conductance `g_W_K` through `area_m2` with `extra` (m²K/W, negative: less) resistance in series, as a
// lumped cell's centroid moves away from or towards the contact (PartModel::lump, recentre); never more
// than four times what it was (the centroid of a bead's slices lies inside it).
double in_series(double g_W_K, double extra, double area_m2) {
  return area_m2 > 0.0 ? 1.0 / std::max(1.0 / g_W_K + extra / area_m2, 0.25 / g_W_K) : g_W_K;
}

// The conductivity tensor of a cell whose bead runs along `along` (a unit vector in plan).
Eigen::Matrix3d conductivity(const Eigen::Vector2d& along, const Material& m) {
  const Eigen::Vector3d t(along.x(), along.y(), 0.0);
  const Eigen::Vector3d s(-along.y(), along.x(), 0.0);
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  return m.conductivity_along_W_mK * t * t.transpose() + m.conductivity_across_W_mK * s * s.transpose() +
         m.conductivity_through_W_mK * z * z.transpose();
}

}  // namespace

PartModel::PartModel(const ThermalMesh& mesh, const Material& material, const Environment& env)
    : n_(mesh.cells.size()),
      material_(material),
      deposition_c_(material.deposition_temp_c),
      ambient_c_(env.ambient_c),
      bed_c_(env.bed_temp_c),
      eps_sigma_(material.emissivity * kStefanBoltzmann_W_m2K4),
      table_radiant_c_(env.bed_insulated ? env.ambient_c : env.bed_temp_c) {
  fan_full_h_ = env.fan_convection_W_m2K;
  birth_c_.resize(n_);
  for (std::size_t i = 0; i < n_; ++i) birth_c_[i] = deposition_c_ + mesh.cells[i].deposition_offset_k;
  centroid_mm_.resize(n_);
  for (std::size_t i = 0; i < n_; ++i) centroid_mm_[i] = mesh.cells[i].centroid_mm;
  mass_kg_.resize(n_);
  exposed_m2_.resize(n_);
  exposed_rarea_.resize(n_);
  table_W_K_.resize(n_);
  table_area_m2_.resize(n_);
  h_.resize(n_);
  const Eigen::Vector3d inverse_k(1.0 / material.conductivity_along_W_mK,
                                  1.0 / material.conductivity_across_W_mK,
                                  1.0 / material.conductivity_through_W_mK);
  for (std::size_t i = 0; i < n_; ++i) {
    const ThermalCell& c = mesh.cells[i];
    h_[i] = env.convection_at(c.centroid_mm.z() - mesh.table_z_mm);
    mass_kg_[i] = material.density_kg_m3 * c.volume_mm3 * kM3PerMm3;
    exposed_m2_[i] = c.open_area_mm2 * kM2PerMm2;
    open_m2_.push_back(exposed_m2_[i]);
    exposed_rarea_[i] = c.open_depth_mm3.dot(inverse_k) * kM3PerMm3;
    // The table's contact in series with the conduction from the centroid down to the table.
    const double down_m = std::max(c.centroid_mm.z() - mesh.table_z_mm, 0.0) * kMPerMm;
    table_area_m2_[i] = c.table_area_mm2 * kM2PerMm2;
    table_W_K_[i] = env.bed_insulated || c.table_area_mm2 <= 0.0
                        ? 0.0
                        : c.table_area_mm2 * kM2PerMm2 /
                              (1.0 / env.bed_contact_W_m2K + down_m / material.conductivity_through_W_mK);
  }
  list_neighbours(mesh, material);
  // Every contact is open surface until the neighbour is born.
  for (std::size_t i = 0; i < n_; ++i)
    for (std::size_t k = first_[i]; k < first_[i + 1]; ++k) {
      exposed_m2_[i] += nb_area_m2_[k];
      exposed_rarea_[i] += nb_rarea_[k];
    }
  sky_m2_ = open_m2_;
  table_view_m2_.assign(n_, 0.0);
  eps_sigma_view_.assign(n_, eps_sigma_);
  radiant_c_.assign(n_, ambient_c_);
  for (std::size_t i = 0; i < n_; ++i) update_air(i);
  loss_.assign(n_, 0.0);
  born_end_.assign(first_.begin(), first_.end() - 1);
  born_g_.assign(n_, 0.0);
}

void PartModel::list_neighbours(const ThermalMesh& mesh, const Material& material) {
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
    const Eigen::Matrix3d k_a = conductivity(a.along, material), k_b = conductivity(b.along, material);
    const double k_n = 0.5 * normal.dot((k_a + k_b) * normal);
    const double distance = std::max(std::abs((b.centroid_mm - a.centroid_mm).dot(normal)), half_voxel);
    const double g = k_n * area * kM2PerMm2 / (distance * kMPerMm);
    // Each cell's half of the contact, from its centroid to the shared faces along the normal.
    const double to_face = l.face_centroid_mm.allFinite()
                               ? std::abs((l.face_centroid_mm - a.centroid_mm).dot(normal))
                               : 0.5 * distance;
    const double a_half = std::min(to_face, distance), b_half = distance - a_half;
    const double area_m2 = area * kM2PerMm2;
    const double ka_n = normal.dot(k_a * normal), kb_n = normal.dot(k_b * normal);
    neighbours[next[l.a]++] = {l.b, g, area_m2, area_m2 * a_half * kMPerMm / ka_n,
                               (normal / ka_n).cast<float>()};
    neighbours[next[l.b]++] = {l.a, g, area_m2, area_m2 * b_half * kMPerMm / kb_n,
                               (-normal / kb_n).cast<float>()};
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
  nb_rarea_.reserve(neighbours.size());
  nb_w_.reserve(neighbours.size());
  for (const Neighbour& nb : neighbours) {
    nb_cell_.push_back(nb.cell);
    nb_g_.push_back(nb.conductance_W_K);
    nb_area_m2_.push_back(nb.area_m2);
    nb_rarea_.push_back(nb.rarea);
    nb_w_.push_back(nb.w);
  }
}

void PartModel::update_air(std::size_t i) {
  const double exposed = exposed_m2_[i], table = table_view_m2_[i];
  if (table == 0.0 && sky_m2_[i] == open_m2_[i]) {  // it sees only the sky
    eps_sigma_view_[i] = eps_sigma_;
    radiant_c_[i] = ambient_c_;
    return;
  }
  // The faces towards neighbours not yet born see the sky.
  const double sky = std::max(exposed - open_m2_[i], 0.0) + sky_m2_[i];
  const double seen = sky + table;
  eps_sigma_view_[i] = exposed > 0.0 ? eps_sigma_ * std::clamp(seen / exposed, 0.0, 1.0) : eps_sigma_;
  radiant_c_[i] = ambient_c_;
  if (table > 0.0 && seen > 0.0) {
    const double ta = ambient_c_ + kKelvinOffset, tb = table_radiant_c_ + kKelvinOffset;
    const double t4 = (sky * ta * ta * ta * ta + table * tb * tb * tb * tb) / seen;
    radiant_c_[i] = std::sqrt(std::sqrt(t4)) - kKelvinOffset;
  }
}

void PartModel::set_capacity(std::size_t capacity) {
  BT_CHECK(capacity >= born_ && capacity <= n_);
  cap_ = capacity;
  partition();
}

std::vector<double> PartModel::local(std::span<const double> full) const {
  BT_CHECK_OP(full.size(), ==, cap_ + 1);
  std::vector<double> out(full.begin() + static_cast<std::ptrdiff_t>(lo_),
                          full.begin() + static_cast<std::ptrdiff_t>(hi_));
  out.push_back(comm_ == nullptr || comm_->rank() == 0 ? full[cap_] : 0.0);
  return out;
}

std::span<const double> PartModel::gather(std::span<const double> local, std::vector<double>& buffer) const {
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

double PartModel::time_constant_s(std::size_t i) const {
  const auto cell = static_cast<std::uint32_t>(i);
  return time_constant_s(std::span<const std::uint32_t>(&cell, 1));
}

double PartModel::half_shift(std::size_t i, std::size_t k, const Eigen::Vector3d& centroid_mm) const {
  return (centroid_mm_[i] - centroid_mm).dot(nb_w_[k].cast<double>()) * kMPerMm;
}

double PartModel::table_from(std::size_t i, double centroid_z_mm) const {
  const double higher_m = (centroid_z_mm - centroid_mm_[i].z()) * kMPerMm;
  return in_series(table_W_K_[i], higher_m / material_.conductivity_through_W_mK, table_area_m2_[i]);
}

double PartModel::time_constant_s(std::span<const std::uint32_t> cells) const {
  double c = 0.0, g = 0.0, mass = 0.0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const std::uint32_t i : cells) mass += mass_kg_[i], centroid += mass_kg_[i] * centroid_mm_[i];
  if (mass > 0.0) centroid /= mass;
  const bool moves = cells.size() > 1;
  for (const std::uint32_t i : cells) {
    c += heat_capacity(i, deposition_c_);
    if (table_W_K_[i] > 0.0) g += moves ? table_from(i, centroid.z()) : table_W_K_[i];
    for (std::size_t k = first_[i]; k < first_[i + 1]; ++k) {
      if (std::find(cells.begin(), cells.end(), nb_cell_[k]) != cells.end()) continue;
      g += moves ? in_series(nb_g_[k], half_shift(i, k, centroid), nb_area_m2_[k]) : nb_g_[k];
    }
  }
  return g > 0.0 ? c / g : std::numeric_limits<double>::infinity();
}

void PartModel::birth(std::size_t end, std::span<double> y) {
  for (std::size_t i = born_; i < end; ++i) {
    y[i] = birth_c_[i];
    for (std::size_t k = first_[i]; k < first_[i + 1]; ++k) {
      const std::uint32_t j = nb_cell_[k];
      if (j < end) close_face(i, k);
      if (j < born_) close_face(j, face_towards(j, static_cast<std::uint32_t>(i)));
    }
    energy_in_J_ += mass_kg_[i] * material_.enthalpy_J_kg(ambient_c_, birth_c_[i]);
  }
  const std::size_t before = born_;
  born_ = end;
  for (std::size_t i = before; i < end; ++i) {
    find_born_end(i);
    for (std::size_t k = first_[i]; k < first_[i + 1] && nb_cell_[k] < before; ++k)
      find_born_end(nb_cell_[k]);
  }
}

void PartModel::lump(std::span<const std::uint32_t> to, std::vector<double>& y,
                     std::span<const std::uint8_t> recentre) {
  const std::size_t m = n_ == 0 ? 0 : std::size_t{to[n_ - 1]} + 1;
  std::vector<double> mass(m, 0.0), exposed(m, 0.0), rarea(m, 0.0), table(m, 0.0), h_area(m, 0.0),
      h_sum(m, 0.0), count(m, 0.0), enthalpy(m, 0.0), open(m, 0.0), sky(m, 0.0), table_view(m, 0.0),
      birth(m, 0.0);
  std::vector<Eigen::Vector3d> centroid(m, Eigen::Vector3d::Zero());
  for (std::size_t i = 0; i < n_; ++i) {
    const std::size_t g = to[i];
    mass[g] += mass_kg_[i];
    centroid[g] += mass_kg_[i] * centroid_mm_[i];
    exposed[g] += exposed_m2_[i];
    rarea[g] += exposed_rarea_[i];
    open[g] += open_m2_[i];
    sky[g] += sky_m2_[i];
    table_view[g] += table_view_m2_[i];
    birth[g] += mass_kg_[i] * birth_c_[i];  // a cell not born yet stays a run of one
    h_area[g] += h_[i] * exposed_m2_[i];
    h_sum[g] += h_[i];
    count[g] += 1.0;
    if (i < cap_) enthalpy[g] += mass_kg_[i] * material_.enthalpy_J_kg(ambient_c_, y[i]);
  }
  std::vector<double> h(m);
  for (std::size_t g = 0; g < m; ++g) h[g] = exposed[g] > 0.0 ? h_area[g] / exposed[g] : h_sum[g] / count[g];
  for (std::size_t g = 0; g < m; ++g) centroid[g] /= mass[g];
  // The table's contact in series with the half cell down to it, from the new centroid where recentred.
  std::vector<double> table_area(m, 0.0);
  for (std::size_t i = 0; i < n_; ++i) {
    const std::size_t g = to[i];
    table_area[g] += table_area_m2_[i];
    if (table_W_K_[i] <= 0.0) continue;
    const bool moves = g < recentre.size() && recentre[g] != 0;
    table[g] += moves ? table_from(i, centroid[g].z()) : table_W_K_[i];
  }
  std::vector<std::size_t> first;
  std::vector<std::uint32_t> nb_cell;
  std::vector<double> nb_g, nb_area, nb_rarea;
  std::vector<Eigen::Vector3f> nb_w;
  merge_neighbours(to, m, centroid, recentre, first, nb_w, nb_cell, nb_g, nb_area, nb_rarea);
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
  for (std::size_t g = 0; g < m; ++g) birth[g] /= mass[g];
  birth_c_ = std::move(birth);
  mass_kg_ = std::move(mass);
  exposed_m2_ = std::move(exposed);
  exposed_rarea_ = std::move(rarea);
  table_W_K_ = std::move(table);
  open_m2_ = std::move(open);
  sky_m2_ = std::move(sky);
  table_view_m2_ = std::move(table_view);
  eps_sigma_view_.assign(n_, eps_sigma_);
  radiant_c_.assign(n_, ambient_c_);
  for (std::size_t i = 0; i < n_; ++i) update_air(i);
  h_ = std::move(h);
  first_ = std::move(first);
  nb_cell_ = std::move(nb_cell);
  nb_g_ = std::move(nb_g);
  nb_area_m2_ = std::move(nb_area);
  nb_rarea_ = std::move(nb_rarea);
  nb_w_ = std::move(nb_w);
  centroid_mm_ = std::move(centroid);
  table_area_m2_ = std::move(table_area);
  loss_.assign(n_, 0.0);
  born_ = born;
  born_end_.resize(n_);
  born_g_.resize(n_);
  for (std::size_t i = 0; i < n_; ++i) find_born_end(i);
  cap_ = cap;
  y = std::move(state);
}

void PartModel::merge_neighbours(std::span<const std::uint32_t> to, std::size_t m,
                                 std::span<const Eigen::Vector3d> centroid_mm,
                                 std::span<const std::uint8_t> recentre, std::vector<std::size_t>& first,
                                 std::vector<Eigen::Vector3f>& nb_w, std::vector<std::uint32_t>& nb_cell,
                                 std::vector<double>& nb_g, std::vector<double>& nb_area,
                                 std::vector<double>& nb_rarea) const {
  // Whether old cell i's new cell is recentred; half_shift of its contact k to that cell's centroid.
  const auto recentred = [&](std::size_t i) { return to[i] < recentre.size() && recentre[to[i]] != 0; };
  const auto shift = [&](std::size_t i, std::size_t k) { return half_shift(i, k, centroid_mm[to[i]]); };
  // The members' lists, renumbered (still in order, as `to` keeps order), merged per neighbour.
  first.assign(m + 1, 0);
  nb_cell.reserve(nb_cell_.size());
  nb_g.reserve(nb_cell_.size());
  nb_area.reserve(nb_cell_.size());
  nb_rarea.reserve(nb_cell_.size());
  nb_w.reserve(nb_cell_.size());
  struct Entry {
    std::uint32_t neighbour;  // new
    std::size_t k;            // old entry
    std::size_t member;       // old cell
    bool operator<(const Entry& o) const {
      return neighbour != o.neighbour ? neighbour < o.neighbour : k < o.k;
    }
  };
  std::vector<Entry> entries;
  for (std::size_t i = 0; i < n_;) {
    const std::uint32_t g = to[i];
    std::size_t j = i;
    entries.clear();
    for (; j < n_ && to[j] == g; ++j)
      for (std::size_t k = first_[j]; k < first_[j + 1]; ++k)
        if (to[nb_cell_[k]] != g) entries.push_back({to[nb_cell_[k]], k, j});
    std::sort(entries.begin(), entries.end());
    for (std::size_t e = 0; e < entries.size(); ++e) {
      if (e == 0 || entries[e].neighbour != entries[e - 1].neighbour) {
        if (e > 0 && nb_area.back() > 0.0) nb_w.back() /= static_cast<float>(nb_area.back());
        nb_cell.push_back(entries[e].neighbour);
        nb_g.push_back(0.0);
        nb_area.push_back(0.0);
        nb_rarea.push_back(0.0);
        nb_w.push_back(Eigen::Vector3f::Zero());
      }
      const std::size_t k = entries[e].k, member = entries[e].member;
      const double area = nb_area_m2_[k];
      double g_k = nb_g_[k], rarea_k = nb_rarea_[k];
      const std::uint32_t other = nb_cell_[k];
      if (area > 0.0 && (recentred(member) || recentred(other))) {  // each side from its new centroid
        const double mine = recentred(member) ? shift(member, k) : 0.0;
        const double theirs =
            recentred(other) ? shift(other, face_towards(other, static_cast<std::uint32_t>(member))) : 0.0;
        g_k = in_series(g_k, mine + theirs, area);
        rarea_k = std::max(rarea_k + area * mine, 0.25 * rarea_k);
      }
      nb_g.back() += g_k;
      nb_area.back() += area;
      nb_rarea.back() += rarea_k;
      nb_w.back() += static_cast<float>(area) * nb_w_[k];
    }
    if (!entries.empty() && nb_area.back() > 0.0) nb_w.back() /= static_cast<float>(nb_area.back());
    first[g + 1] = nb_cell.size();
    i = j;
  }
}

double PartModel::energy_stored_J(std::span<const double> y) const {
  double e = 0.0;
  for (std::size_t i = 0; i < born_; ++i) e += mass_kg_[i] * material_.enthalpy_J_kg(ambient_c_, y[i]);
  return e;
}

void PartModel::set_tolerances(double rel_tol, double abs_tol_k) {
  rel_tol_ = rel_tol;
  abs_tol_k_ = abs_tol_k;
  double total = 0.0;
  for (std::size_t i = 0; i < n_; ++i) total += heat_capacity(i, deposition_c_);
  abs_tol_J_ = std::max(total * abs_tol_k, 1e-12);
}

void PartModel::rhs(double /*t*/, std::span<const double> y, std::span<double> ydot) {
  const double* all = with_halo(y, halo_y_);
  const std::size_t end = owned_born();
  for_range(lo_, end, [&](std::size_t i) { ydot[i - lo_] = rate(i, all, loss_[i]); });
  double q = 0.0;
  for (std::size_t i = lo_; i < end; ++i) q += loss_[i];
  for (std::size_t i = end; i < hi_; ++i) ydot[i - lo_] = 0.0;
  ydot[hi_ - lo_] = q;
}

void PartModel::jacobian_times_setup(double /*t*/, std::span<const double> y) {
  const std::size_t end = owned_born();
  jt_capacity_.resize(hi_ - lo_);
  jt_loss_derivative_.resize(hi_ - lo_);
  for_range(lo_, end, [&](std::size_t i) {
    const double yi = y[i - lo_];
    jt_capacity_[i - lo_] = heat_capacity(i, yi);
    jt_loss_derivative_[i - lo_] = loss_derivative(i, yi);
  });
}

void PartModel::jacobian_times(double /*t*/, std::span<const double> /*y*/, std::span<const double> v,
                               std::span<double> jv) {
  const std::size_t end = owned_born();
  const double* all_v = with_halo(v, halo_v_);
  BT_CHECK_OP(jt_capacity_.size(), ==, hi_ - lo_);
  for_range(lo_, end, [&](std::size_t i) {
    double sum = 0.0;
    const double vi = all_v[i];
    for (std::size_t k = first_[i], e = born_end_[i]; k < e; ++k) sum += nb_g_[k] * (all_v[nb_cell_[k]] - vi);
    const double d_loss = jt_loss_derivative_[i - lo_] * vi;
    loss_[i] = d_loss;
    jv[i - lo_] = (sum - d_loss) / jt_capacity_[i - lo_];
  });
  double q = 0.0;
  for (std::size_t i = lo_; i < end; ++i) q += loss_[i];
  for (std::size_t i = end; i < hi_; ++i) jv[i - lo_] = 0.0;
  jv[hi_ - lo_] = q;
}

void PartModel::jacobian_diagonal(double /*t*/, std::span<const double> y, std::span<double> diagonal) {
  const std::size_t end = owned_born();
  for_range(lo_, end, [&](std::size_t i) {
    diagonal[i - lo_] = -(born_g_[i] + loss_derivative(i, y[i - lo_])) / heat_capacity(i, y[i - lo_]);
  });
  for (std::size_t i = end; i < hi_; ++i) diagonal[i - lo_] = 0.0;
  diagonal[hi_ - lo_] = 0.0;
}

void PartModel::error_weights(std::span<const double> y, std::span<double> weights) {
  const std::size_t cells = hi_ - lo_;
  for (std::size_t i = 0; i < cells; ++i) weights[i] = 1.0 / (rel_tol_ * std::abs(y[i]) + abs_tol_k_);
  weights[cells] = 1.0 / (rel_tol_ * std::abs(y[cells]) + abs_tol_J_);
}

void PartModel::find_born_end(std::size_t i) {
  double g = 0.0;
  std::size_t k = first_[i];
  for (; k < first_[i + 1] && nb_cell_[k] < born_; ++k) g += nb_g_[k];
  born_end_[i] = k;
  born_g_[i] = g;
}

std::size_t PartModel::face_towards(std::size_t i, std::uint32_t j) const {
  const auto begin = nb_cell_.begin() + static_cast<std::ptrdiff_t>(first_[i]);
  const auto end = nb_cell_.begin() + static_cast<std::ptrdiff_t>(first_[i + 1]);
  const auto it = std::lower_bound(begin, end, j);
  BT_CHECK(it != end && *it == j);
  return static_cast<std::size_t>(it - nb_cell_.begin());
}

void PartModel::partition() {
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
  for (std::size_t r = 0; r < ranks; ++r) part_counts_[r] = static_cast<int>(bounds_[r + 1] - bounds_[r] + 1);
  partition_halo(ranks, me);
}

void PartModel::partition_halo(std::size_t ranks, std::size_t me) {
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

const double* PartModel::with_halo(std::span<const double> local, std::vector<double>& all) const {
  if (comm_ == nullptr) return local.data();
  all.resize(cap_);
  std::copy(local.begin(), local.begin() + static_cast<std::ptrdiff_t>(hi_ - lo_),
            all.begin() + static_cast<std::ptrdiff_t>(lo_));
  for (std::size_t k = 0; k < send_cells_.size(); ++k) send_buffer_[k] = local[send_cells_[k] - lo_];
  comm_->exchange(send_buffer_, send_counts_, recv_buffer_, recv_counts_);
  for (std::size_t k = 0; k < recv_cells_.size(); ++k) all[recv_cells_[k]] = recv_buffer_[k];
  return all.data();
}

}  // namespace beadtwin::thermal
