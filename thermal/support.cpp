#include "thermal/support.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <openvdb/openvdb.h>

#include "core/error.hpp"
#include "thermal/mesh.hpp"

namespace beadtwin::thermal {
namespace {

constexpr double kGravity_m_s2 = 9.80665;
// A contact whose normal is within 60° of vertical carries the cell above it (as ThermalLink's on-top).
constexpr double kOnTopCos = 0.5;
// Gaps in the wall's line across the bead that still count as the same wall (the triangles between round
// beads side by side), voxels.
constexpr int kBridgedVoxels = 2;
// The table of ∫ 1/η dT: its spacing, K, and how far it reaches above the deposition temperature, K (the
// hot edge's search shifts columns above it; beyond the table the integral is taken by Simpson's rule,
// with sub-intervals no wider than kSimpsonStepK). 1/η changes by a third per kelvin at most near the
// glass transition (WLF's C1/C2 there), so 1/η is exponential within a step to a few parts in 10^5.
constexpr double kTableStepK = 0.05;
constexpr double kTableAboveDepositionK = 100.0;
constexpr double kSimpsonStepK = 0.25;
// Segments of a column whose ends differ by less than this, K, are taken at one temperature.
constexpr double kUniformK = 1e-6;
// The hot edge's search (Support::judge_column): steps, their largest size, K, and the tolerance on
// ln(δ / allowed) (0.005: half a per cent of the allowed slump, a few hundredths of a kelvin).
constexpr int kSecantSteps = 12;
constexpr double kMaxSecantStepK = 40.0;
constexpr double kSecantTolerance = 0.005;

// ∫ f over [0, x] of a step of width h whose ends have f = a and f = b (x = h: the whole step), f taken as
// exponential between them (linear where either end is 0).
double exponential_part(double a, double b, double h, double x) {
  if (!(a > 0.0) || !(b > 0.0)) return a * x + (b - a) * x * x / (2.0 * h);
  const double rx = std::log(b / a) * x / h;
  return std::abs(rx) < 1e-6 ? a * x * (1.0 + 0.5 * rx) : a * x * std::expm1(rx) / rx;
}
double exponential_part(double a, double b, double h) {
  return exponential_part(a, b, h, h);
}

// Material voxels in a straight horizontal line from `centre` along `dir`, both ways: the wall's width, mm.
double width_across(const openvdb::Int32Grid& grid, const Eigen::Vector3d& centre, const Eigen::Vector3d& dir,
                    double vs) {
  openvdb::tree::ValueAccessor<const openvdb::Int32Tree> at(grid.tree());
  const auto material = [&](int k) {
    const Eigen::Vector3d p = centre + dir * (k * vs);
    const openvdb::Coord ijk(static_cast<int>(std::floor(p.x() / vs)),
                             static_cast<int>(std::floor(p.y() / vs)),
                             static_cast<int>(std::floor(p.z() / vs)));
    return at.getValue(ijk) >= 0;
  };
  const auto reach = [&](int sign) {
    int last = 0;
    for (int k = 1; k - last <= kBridgedVoxels + 1; ++k)
      if (material(sign * k)) last = k;
    return last;
  };
  return (reach(1) + reach(-1) + 1) * vs;
}

}  // namespace

std::vector<SupportCell> support_cells(const ThermalMesh& mesh, const Toolpath* toolpath) {
  const std::size_t n = mesh.cells.size();
  std::vector<SupportCell> out(n);
  std::vector<double> below_area(n, 0.0);
  for (const ThermalLink& l : mesh.links) {
    const double area = l.area_mm2();
    if (!(area > 0.0)) continue;
    // On an older cell; or, for the slices of one bead through its height (born together, its top slice
    // first), on a younger one of the same bead. Nothing rests on a cell laid after it otherwise, so the
    // walk down a column always ends.
    const double up = l.area_vector_mm2.z();
    const bool same_bead =
        mesh.cells[l.a].move == mesh.cells[l.b].move && mesh.cells[l.a].birth_s == mesh.cells[l.b].birth_s;
    const std::uint32_t above = up > 0.0 ? l.b : l.a, under = up > 0.0 ? l.a : l.b;
    if (std::abs(up) < kOnTopCos * area || (above == l.a && !same_bead) || area <= below_area[above])
      continue;
    below_area[above] = area;
    out[above].below = under;
  }
  // A cell rests on a younger one only within its own bead (above), whose top slice comes first.
  for (std::uint32_t c = 0; c < n; ++c) out[c].bead_top = c;
  for (std::uint32_t c = 0; c < n; ++c)
    if (const std::uint32_t b = out[c].below; b != SupportCell::kNone && b > c)
      out[b].bead_top = out[c].bead_top;
  const double vs = mesh.voxel_size_mm;
  for (std::size_t c = 0; c < n; ++c) {
    const ThermalCell& cell = mesh.cells[c];
    const Move* move = toolpath != nullptr ? &toolpath->moves[cell.move] : nullptr;
    SupportCell& s = out[c];
    const double z = cell.centroid_mm.z();
    double half = move != nullptr ? 0.5 * move->layer_height_mm : 0.0;
    if (s.below != SupportCell::kNone)
      half = 0.5 * (z - mesh.cells[s.below].centroid_mm.z());
    else if (cell.table_area_mm2 > 0.0)
      half = z - mesh.table_z_mm;
    half = std::max(half, 0.0);
    s.birth_s = cell.birth_s;
    s.centre_z_mm = static_cast<float>(z);
    s.top_z_mm = static_cast<float>(z + half);
    s.layer_height_mm = static_cast<float>(move != nullptr ? move->layer_height_mm : 2.0 * half);
    if (move != nullptr)
      s.speed_mm_s =
          static_cast<float>(move->duration_s > 0.0 ? move->length_mm() / move->duration_s : move->feed_mm_s);
    if (mesh.cell_grid) {
      const Eigen::Vector3d across(-cell.along.y(), cell.along.x(), 0.0);
      s.wall_width_mm =
          static_cast<float>(width_across(*mesh.cell_grid, cell.centroid_mm, across.normalized(), vs));
    } else if (half > 0.0) {
      s.wall_width_mm = static_cast<float>(std::sqrt(cell.volume_mm3 / (2.0 * half)));
    }
  }
  return out;
}

Support::Support(const Material& material, const SupportLoad& load)
    : reptation_(material),
      deposition_c_(material.deposition_temp_c),
      softening_c_(std::isnan(material.softening_temp_c) ? material.glass_transition_c
                                                         : material.softening_temp_c),
      viscosity_ref_Pa_s_(material.viscosity_ref_Pa_s),
      weight_Pa_per_mm_(material.density_kg_m3 * kGravity_m_s2 * 1e-3),
      allowed_(material.max_slump),
      load_(load) {
  if (!(viscosity_ref_Pa_s_ > 0.0))
    throw InputError({}, "fusion.viscosity", fmt::format("must be positive, is {}", viscosity_ref_Pa_s_));
  if (!(allowed_ > 0.0))
    throw InputError({}, "fusion.max_slump", fmt::format("must be positive, is {}", allowed_));
  const double top_c = std::max(deposition_c_, softening_c_) + kTableAboveDepositionK;
  const auto points = static_cast<std::size_t>(std::ceil((top_c - softening_c_) / kTableStepK)) + 1;
  table_fluidity_.resize(points);
  table_cumulative_.assign(points, 0.0);
  for (std::size_t k = 0; k < points; ++k) table_fluidity_[k] = raw_fluidity(node_c(k));
  for (std::size_t k = 1; k < points; ++k)
    table_cumulative_[k] =
        table_cumulative_[k - 1] + exponential_part(table_fluidity_[k - 1], table_fluidity_[k], kTableStepK);
}

double Support::node_c(std::size_t k) const {
  return softening_c_ + static_cast<double>(k) * kTableStepK;
}

double Support::raw_fluidity(double temp_c) const {
  const double log_time = reptation_.log_time(temp_c);
  return std::isfinite(log_time) ? std::exp(-log_time) / viscosity_ref_Pa_s_ : 0.0;
}

double Support::fluidity(double temp_c) const {
  return temp_c > softening_c_ ? raw_fluidity(temp_c) : 0.0;
}

double Support::cumulative(double temp_c) const {
  if (!(temp_c > softening_c_)) return 0.0;
  const double x = (temp_c - softening_c_) / kTableStepK;
  const std::size_t last = table_cumulative_.size() - 1;
  if (x < static_cast<double>(last)) {
    const auto k = static_cast<std::size_t>(x);
    return table_cumulative_[k] +
           exponential_part(table_fluidity_[k], table_fluidity_[k + 1], kTableStepK, temp_c - node_c(k));
  }
  const double top_c = node_c(last);
  const int n = 2 * std::max(1, static_cast<int>(std::ceil((temp_c - top_c) / (2.0 * kSimpsonStepK))));
  double sum = 0.0;
  for (int k = 0; k <= n; ++k)
    sum +=
        raw_fluidity(top_c + (temp_c - top_c) * k / n) * (k == 0 || k == n ? 1.0 : (k % 2 == 1 ? 4.0 : 2.0));
  return table_cumulative_[last] + sum * (temp_c - top_c) / (3.0 * n);
}

double Support::fluidity_integral(double low_c, double high_c) const {
  return cumulative(high_c) - cumulative(low_c);
}

SupportResult Support::judge(std::span<const SupportCell> cells, std::uint32_t older, std::uint32_t younger,
                             double min_load_s, const std::function<double(std::uint32_t)>& temp_c,
                             double reference_c) const {
  // The column under the new bead, walked down while it is soft and one cell further, where it is not (or
  // to the table): the substrate cell uniform from its top to its centre, linear between centres, the last
  // cell uniform down to its bottom.
  // Reused per thread: a landing is judged at every birth, and its column is a handful of points.
  thread_local std::vector<double> z, t;
  z.assign(1, cells[older].top_z_mm);
  t.assign(1, temp_c(older));
  std::uint32_t c = older, deepest_soft = older;
  for (;;) {
    z.push_back(cells[c].centre_z_mm);
    t.push_back(temp_c(c));
    if (!(t.back() > softening_c_)) break;
    deepest_soft = c;
    if (cells[c].below == SupportCell::kNone) break;
    c = cells[c].below;
  }
  z.push_back(2.0 * cells[c].centre_z_mm - cells[c].top_z_mm);
  t.push_back(t.back());
  const SupportCell& y = cells[younger];
  const double soft_for_s = std::max(y.birth_s - cells[deepest_soft].birth_s, min_load_s);
  return judge_column(z, t, cells[older].wall_width_mm, y.layer_height_mm, y.speed_mm_s, soft_for_s,
                      reference_c);
}

Support::Slump Support::slump(std::span<const double> z_mm, std::span<const double> temp_c, double offset_k,
                              double wall_width_mm, double layer_height_mm, double speed_mm_s,
                              double soft_for_s) const {
  // H and ∫ dz / η over the soft part, from the top down to where the temperature first falls to T_s.
  Slump out;
  double compliance = 0.0;  // mm/(Pa·s)
  for (std::size_t i = 0; i + 1 < z_mm.size(); ++i) {
    const double t0 = temp_c[i] + offset_k, t1 = temp_c[i + 1] + offset_k;
    if (!(t0 > softening_c_)) break;
    double length = z_mm[i] - z_mm[i + 1];
    const bool ends = !(t1 > softening_c_);
    if (ends) length *= (t0 - softening_c_) / (t0 - t1);
    const double t_end = ends ? softening_c_ : t1;
    // T linear in z over the segment: ∫ dz/η = length · ∫ dT/η / ΔT.
    if (std::abs(t0 - t_end) < kUniformK)
      compliance += fluidity(0.5 * (t0 + t_end)) * length;
    else
      compliance += length * (cumulative(t0) - cumulative(t_end)) / (t0 - t_end);
    out.soft_height_mm += length;
    if (ends) break;
  }
  const double h = out.soft_height_mm;
  if (!(h > 0.0)) return out;
  const double squeeze = 3.0 + wall_width_mm * wall_width_mm / (4.0 * h * h);
  const double roller_s = speed_mm_s > 0.0 ? load_.roller_contact_mm / speed_mm_s : 0.0;
  const double passes = layer_height_mm > 0.0 ? std::max(1.0, h / layer_height_mm) : 1.0;
  const double impulse = weight_Pa_per_mm_ * (h + layer_height_mm) * soft_for_s +
                         load_.roller_pressure_Pa * roller_s * passes;  // Pa·s
  out.slump_mm = impulse * compliance / squeeze;
  return out;
}

SupportResult Support::judge_column(std::span<const double> z_mm, std::span<const double> temp_c,
                                    double wall_width_mm, double layer_height_mm, double speed_mm_s,
                                    double soft_for_s, double reference_c) const {
  BT_CHECK(z_mm.size() == temp_c.size() && z_mm.size() >= 2);
  if (std::isnan(reference_c)) reference_c = temp_c[0];
  SupportResult r;
  r.wall_width_mm = wall_width_mm;
  r.allowed_mm = allowed_ * layer_height_mm;
  const auto at = [&](double offset_k) {
    return slump(z_mm, temp_c, offset_k, wall_width_mm, layer_height_mm, speed_mm_s, soft_for_s);
  };
  const Slump now = at(0.0);
  r.soft_height_mm = now.soft_height_mm;
  r.slump_mm = now.slump_mm;
  r.limit_c = std::numeric_limits<double>::infinity();
  if (!(r.allowed_mm > 0.0)) return r;
  // The hot edge: the whole column warmer or cooler by one offset until it slumps by the allowed amount.
  // ln δ is close to linear in the offset (the viscosity's shift is about exponential over tens of kelvin):
  // a secant from the column as it is (or from just soft at its top) finds it in a few steps.
  const auto gap = [&](double offset_k) {
    const double d = at(offset_k).slump_mm;
    return std::log(std::max(d, 1e-30) / r.allowed_mm);  // not soft at all: very far below
  };
  double x0 = now.slump_mm > 0.0 ? 0.0 : softening_c_ - temp_c[0] + 1.0, x1 = x0 + 5.0;
  double f0 = gap(x0), f1 = gap(x1);
  for (int k = 0; k < kSecantSteps && f1 != f0; ++k) {
    const double step = std::clamp(-f1 * (x1 - x0) / (f1 - f0), -kMaxSecantStepK, kMaxSecantStepK);
    x0 = x1, f0 = f1;
    x1 += step;
    f1 = gap(x1);
    if (std::abs(f1) < kSecantTolerance) {
      r.limit_c = std::max(softening_c_, reference_c + x1);
      // Hotter than the bead is laid: no temperature the print reaches slumps it.
      if (r.limit_c > deposition_c_) r.limit_c = std::numeric_limits<double>::infinity();
      break;
    }
  }
  return r;
}

}  // namespace beadtwin::thermal
