#include "slicer/boundary.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

namespace beadtwin::slicer {
namespace {

// The thin walls of a region: the parts a bead's centre cannot reach (what an opening by w/2 removes),
// each as its centre line and width, when no wider than the limit. A piece's width is 2·area/perimeter (exact
// for a long strip) and its centre line runs along its principal axis.
struct ThinWall {
  Eigen::Vector2d a, b;
  double width_mm = 0.0;
};

std::vector<ThinWall> thin_walls(const Polygons& region, double w, double max_width) {
  std::vector<ThinWall> out;
  // The opening leaves numerical slivers along edges it does not quite restore: a second, small opening
  // (a tenth of the bead) drops anything too narrow to take a bead anyway.
  const double sliver = 0.1 * w;
  const Polygons thin =
      offset(offset(difference(region, offset(offset(region, -0.5 * w), 0.5 * w)), -sliver), sliver);
  for (const Polygon& piece : thin) {
    const double area = std::abs(area_mm2({piece}));
    const double perimeter = perimeter_mm({piece});
    if (area <= 0 || perimeter <= 0) continue;
    const double width = 2.0 * area / perimeter;
    // Slivers (a bead corner's worth) are not walls; wide pieces are not thin.
    if (width > max_width || area < 0.25 * w * w) continue;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& p : piece) mean += p;
    mean /= static_cast<double>(piece.size());
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const auto& p : piece) cov += (p - mean) * (p - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
    const Eigen::Vector2d axis = eig.eigenvectors().col(1);
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& p : piece) {
      lo = std::min(lo, (p - mean).dot(axis));
      hi = std::max(hi, (p - mean).dot(axis));
    }
    // The centre line spans the whole piece: a bead's free ends are square (as the deposit lays them), so it
    // meets the passes at one end and the wall's tip at the other.
    out.push_back({mean + lo * axis, mean + hi * axis, width});
  }
  return out;
}

}  // namespace

void lay_boundary(LayerBuilder& b, const SectionParams& s, const std::vector<Polygons>& passes,
                  int layer_in_section) {
  const int laid = static_cast<int>(passes.size());
  const bool reversed = s.boundary.reverse_alternate && layer_in_section % 2 == 1;
  const double advance = layer_in_section * s.seam_offset_mm;
  for (int i = 0; i < laid; ++i) {
    const int k = s.boundary.inside_out ? laid - 1 - i : i;
    for (Polygon loop : passes[static_cast<std::size_t>(k)]) {
      if (s.boundary.min_pass_length_mm > 0 && perimeter_mm({loop}) < s.boundary.min_pass_length_mm) continue;
      if (reversed) std::reverse(loop.begin(), loop.end());
      b.print_pass(start_at(loop, s.start_point_mm, advance), k, s.boundary.lead_in_mm,
                   s.boundary.lead_out_mm, s.boundary.start_stop_overlap * s.bead_width_mm,
                   s.boundary.tangential_lead_out);
    }
  }
}

void lay_thin_walls(LayerBuilder& b, const SectionParams& s, const Polygons& region) {
  const double max_width =
      s.boundary.thin_wall_max_width_mm > 0 ? s.boundary.thin_wall_max_width_mm : s.bead_width_mm;
  for (const ThinWall& t : thin_walls(region, s.bead_width_mm, max_width)) {
    if ((t.b - t.a).norm() < 1e-6) continue;
    b.travel_to(t.a);
    b.event(ExtruderEvent::kMeltOn);
    b.print_thin(t.b, t.width_mm);
    b.event(ExtruderEvent::kMeltOff);
  }
}

}  // namespace beadtwin::slicer
