#include "slicer/fill.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/units.hpp"

namespace beadtwin::slicer {
namespace {

Eigen::Vector2d rotate(const Eigen::Vector2d& p, double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  return {c * p.x() - s * p.y(), s * p.x() + c * p.y()};
}

Polygons rotate(const Polygons& polys, double angle_rad) {
  Polygons out = polys;
  for (auto& poly : out)
    for (auto& p : poly) p = rotate(p, angle_rad);
  return out;
}

// Zigzag (serpentine) fill lines: parallel lines at `pitch` across `region` in direction `angle_rad`,
// clipped to the region and chained so each line starts near where the previous one ended.
std::vector<Polyline> zigzag_lines(const Polygons& region, double angle_rad, double pitch) {
  const Polygons local = rotate(region, -angle_rad);
  double y_min = std::numeric_limits<double>::infinity(), y_max = -y_min;
  double x_min = y_min, x_max = -y_min;
  for (const auto& poly : local)
    for (const auto& p : poly) {
      y_min = std::min(y_min, p.y());
      y_max = std::max(y_max, p.y());
      x_min = std::min(x_min, p.x());
      x_max = std::max(x_max, p.x());
    }
  if (!(y_max > y_min)) return {};
  // Centre the lines in the region so the leftover gap splits evenly on both sides.
  const double span = y_max - y_min;
  const int count = static_cast<int>(std::floor(span / pitch)) + 1;
  const double first = y_min + 0.5 * (span - (count - 1) * pitch);
  std::vector<Polyline> lines;
  for (int i = 0; i < count; ++i) {
    const double y = first + i * pitch;
    lines.push_back({{x_min - 1.0, y}, {x_max + 1.0, y}});
  }
  std::vector<Polyline> clipped = clip_lines(lines, local);
  // Order by scan line, then along it, and rotate back.
  for (auto& l : clipped) {
    if (l.front().x() > l.back().x()) std::reverse(l.begin(), l.end());
  }
  std::sort(clipped.begin(), clipped.end(), [](const Polyline& a, const Polyline& b) {
    if (std::abs(a.front().y() - b.front().y()) > 1e-6) return a.front().y() < b.front().y();
    return a.front().x() < b.front().x();
  });
  for (auto& l : clipped)
    for (auto& p : l) p = rotate(p, angle_rad);
  return clipped;
}

}  // namespace

void lay_fill(LayerBuilder& b, const SectionParams& s, const Polygons& fill_region, int layer_in_section) {
  const double w = s.bead_width_mm;
  const double fill_pitch = w * (1.0 - s.fill.overlap);
  if (fill_region.empty()) return;
  const double angle = (s.fill.angle_deg + layer_in_section * s.fill.angle_step_deg) * kPi / 180.0;
  std::vector<Polyline> lines = zigzag_lines(fill_region, angle, fill_pitch);
  // Serpentine: take the nearest remaining line end each time; link with a printed turn when the turn is
  // short and stays inside the region, otherwise lift and travel.
  std::vector<bool> used(lines.size(), false);
  const Polygons turn_region = offset(fill_region, 0.5 * w);
  bool printing = false;
  for (std::size_t count = 0; count < lines.size(); ++count) {
    std::size_t best = 0;
    bool reverse = false;
    double best_d = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < lines.size(); ++i) {
      if (used[i]) continue;
      const double d0 = (lines[i].front() - b.head()).squaredNorm();
      const double d1 = (lines[i].back() - b.head()).squaredNorm();
      if (d0 < best_d) best_d = d0, best = i, reverse = false;
      if (d1 < best_d) best_d = d1, best = i, reverse = true;
    }
    used[best] = true;
    Polyline line = lines[best];
    if (reverse) std::reverse(line.begin(), line.end());
    const Eigen::Vector2d mid = 0.5 * (line.front() + b.head());
    const bool link = printing && std::sqrt(best_d) <= 1.5 * fill_pitch && contains(turn_region, mid);
    if (!link) {
      if (printing) b.event(ExtruderEvent::kMeltOff);
      b.travel_to(line.front());
      b.event(ExtruderEvent::kMeltOn);
      printing = true;
    } else {
      b.print_segment(line.front(), Feature::kFill, -1);
    }
    for (std::size_t i = 1; i < line.size(); ++i) b.print_segment(line[i], Feature::kFill, -1);
  }
  if (printing) b.event(ExtruderEvent::kMeltOff);
}

}  // namespace beadtwin::slicer
