#include "sim/bead_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "core/error.hpp"

namespace beadtwin::sim {

namespace {

// The sweep seen from one plan position (x, y): everything that does not depend on z.
struct PlanPoint {
  double along = 0.0;          // clamped projection parameter, 0..1
  double core_distance = 0.0;  // horizontal distance to the core's edge, d − a, negative over the core, mm
  double core_excess = 0.0;    // max(d − a, 0), mm
  double centre_z = 0.0;       // height of the profile's centre line here, mm
  double cut_distance = 0.0;   // signed distance to the end cuts, positive outside, mm (−inf without cuts)
  bool kept = true;            // inside both end cuts (half-open)
};

class SweepGeometry {
 public:
  explicit SweepGeometry(const BeadSweep& sweep)
      : sweep_(sweep),
        axis_(sweep.end_xy - sweep.start_xy),
        axis_length2_(axis_.squaredNorm()),
        core_(sweep.profile.core_half_width_mm),
        radius_(sweep.profile.radius_mm),
        has_start_cut_(sweep.start_cut.squaredNorm() > 0.0),
        has_end_cut_(sweep.end_cut.squaredNorm() > 0.0) {}

  double radius() const { return radius_; }

  // How fast the bead's top climbs per mm of plan distance along the move.
  double slope() const {
    if (axis_length2_ <= 0.0) return 0.0;
    return std::abs(sweep_.end_top_mm - sweep_.start_top_mm) / std::sqrt(axis_length2_);
  }

  PlanPoint at(double x, double y) const {
    const Eigen::Vector2d q(x, y);
    PlanPoint p;
    Eigen::Vector2d closest = sweep_.start_xy;
    p.along = 1.0;  // a puddle is complete when its dwell ends
    if (axis_length2_ > 0.0) {
      p.along = std::clamp((q - sweep_.start_xy).dot(axis_) / axis_length2_, 0.0, 1.0);
      closest += p.along * axis_;
    }
    p.core_distance = (q - closest).norm() - core_;
    p.core_excess = std::max(p.core_distance, 0.0);
    p.centre_z = sweep_.start_top_mm + p.along * (sweep_.end_top_mm - sweep_.start_top_mm) - radius_;
    p.cut_distance = -std::numeric_limits<double>::infinity();
    if (has_start_cut_) {
      const double s = (q - sweep_.start_xy).dot(sweep_.start_cut);
      p.cut_distance = std::max(p.cut_distance, -s);
      p.kept = p.kept && s >= 0.0;
    }
    if (has_end_cut_) {
      const double s = (q - sweep_.end_xy).dot(sweep_.end_cut);
      p.cut_distance = std::max(p.cut_distance, s);
      p.kept = p.kept && s < 0.0;
    }
    return p;
  }

 private:
  const BeadSweep& sweep_;
  Eigen::Vector2d axis_;
  double axis_length2_;
  double core_;
  double radius_;
  bool has_start_cut_;
  bool has_end_cut_;
};

// The voxels a sweep can touch: a box in z, and in plan, for each x column i, the band of j the bead's
// outline can reach (a long diagonal bead touches a band, not its whole bounding square).
class Footprint {
 public:
  Footprint(const BeadSweep& sweep, double voxel_size_mm)
      : sweep_(sweep),
        voxel_size_mm_(voxel_size_mm),
        reach_(sweep.profile.core_half_width_mm + sweep.profile.radius_mm) {
    const Eigen::Vector2d lo = sweep.start_xy.cwiseMin(sweep.end_xy).array() - reach_;
    const Eigen::Vector2d hi = sweep.start_xy.cwiseMax(sweep.end_xy).array() + reach_;
    lo_ =
        openvdb::Coord(index(lo.x()), index(lo.y()),
                       index(std::min(sweep.start_top_mm, sweep.end_top_mm) - 2.0 * sweep.profile.radius_mm));
    hi_ = openvdb::Coord(index(hi.x()), index(hi.y()), index(std::max(sweep.start_top_mm, sweep.end_top_mm)));
  }

  const openvdb::Coord& lo() const { return lo_; }
  const openvdb::Coord& hi() const { return hi_; }

  // Inclusive range of j that column i can touch: every point of the bead lies within `reach` of a point
  // of the segment whose x is within `reach` of the column.
  std::pair<int, int> j_range(int i) const {
    const double dx = sweep_.end_xy.x() - sweep_.start_xy.x();
    if (std::abs(dx) <= 1e-9 * voxel_size_mm_) return {lo_.y(), hi_.y()};
    const double t0 = (i * voxel_size_mm_ - reach_ - sweep_.start_xy.x()) / dx;
    const double t1 = ((i + 1) * voxel_size_mm_ + reach_ - sweep_.start_xy.x()) / dx;
    const double ta = std::clamp(std::min(t0, t1), 0.0, 1.0);
    const double tb = std::clamp(std::max(t0, t1), 0.0, 1.0);
    const double dy = sweep_.end_xy.y() - sweep_.start_xy.y();
    const double ya = sweep_.start_xy.y() + ta * dy;
    const double yb = sweep_.start_xy.y() + tb * dy;
    return {std::max(lo_.y(), index(std::min(ya, yb) - reach_)),
            std::min(hi_.y(), index(std::max(ya, yb) + reach_))};
  }

  double voxel_count() const {
    double columns = 0.0;
    for (int i = lo_.x(); i <= hi_.x(); ++i) {
      const auto [j0, j1] = j_range(i);
      columns += std::max(0, j1 - j0 + 1);
    }
    return columns * (hi_.z() - lo_.z() + 1);
  }

 private:
  int index(double v) const { return static_cast<int>(std::floor(v / voxel_size_mm_)); }

  const BeadSweep& sweep_;
  double voxel_size_mm_;
  double reach_;
  openvdb::Coord lo_, hi_;
};

}  // namespace

double BeadSweep::bounding_voxels(double voxel_size_mm) const {
  return Footprint(*this, voxel_size_mm).voxel_count();
}

void rasterize(const BeadSweep& sweep, double voxel_size_mm, int supersample,
               std::vector<CoverageCell>& out) {
  BT_CHECK_OP(voxel_size_mm, >, 0.0);
  BT_CHECK_OP(supersample, >=, 1);
  BT_CHECK_OP(sweep.profile.radius_mm, >, 0.0);
  const SweepGeometry geometry(sweep);
  const Footprint footprint(sweep, voxel_size_mm);
  const double vs = voxel_size_mm;
  const int n = supersample;
  const double step = vs / n;
  const double r = geometry.radius();
  // A column whose centre is farther than its half-diagonal from the bead's outline (in plan) misses it;
  // one that deep inside a level bead is covered over the same height everywhere, so one sample does.
  const double plan_margin = 0.5 * std::sqrt(2.0) * vs;
  const bool level = geometry.slope() == 0.0;

  // Heights the bead spans above each plan sample of the current column.
  struct Span {
    double lo, hi;
  };
  std::vector<Span> spans;
  spans.reserve(static_cast<std::size_t>(n * n));
  const auto add_span = [&spans, r](const PlanPoint& p) {
    if (!p.kept || p.core_excess >= r) return;
    const double half = std::sqrt(r * r - p.core_excess * p.core_excess);
    spans.push_back({p.centre_z - half, p.centre_z + half});
  };

  for (int i = footprint.lo().x(); i <= footprint.hi().x(); ++i) {
    const double x0 = i * vs;
    const auto [j_lo, j_hi] = footprint.j_range(i);
    for (int j = j_lo; j <= j_hi; ++j) {
      const double y0 = j * vs;
      const PlanPoint centre = geometry.at(x0 + 0.5 * vs, y0 + 0.5 * vs);
      const double outline_distance = std::max(centre.core_excess - r, centre.cut_distance);
      if (outline_distance >= plan_margin) continue;
      spans.clear();
      double samples = static_cast<double>(n) * n;
      if (level && centre.core_distance <= -plan_margin && centre.cut_distance <= -plan_margin) {
        add_span(centre);
        samples = 1.0;
      } else {
        for (int sx = 0; sx < n; ++sx)
          for (int sy = 0; sy < n; ++sy)
            add_span(geometry.at(x0 + (sx + 0.5) * step, y0 + (sy + 0.5) * step));
      }
      if (spans.empty()) continue;
      double lo = spans.front().lo, hi = spans.front().hi;
      for (const Span& span : spans) lo = std::min(lo, span.lo), hi = std::max(hi, span.hi);
      const int k_lo = std::max(footprint.lo().z(), static_cast<int>(std::floor(lo / vs)));
      const int k_hi = std::min(footprint.hi().z(), static_cast<int>(std::floor(hi / vs)));
      for (int k = k_lo; k <= k_hi; ++k) {
        const double z0 = k * vs;
        double covered = 0.0;  // mm of the voxel's height, summed over the samples
        for (const Span& span : spans)
          covered += std::max(0.0, std::min(span.hi, z0 + vs) - std::max(span.lo, z0));
        const double fraction = std::min(1.0, covered / (samples * vs));
        if (fraction <= 0.0) continue;
        out.push_back(
            {openvdb::Coord(i, j, k), static_cast<float>(fraction), static_cast<float>(centre.along)});
      }
    }
  }
}

}  // namespace beadtwin::sim
