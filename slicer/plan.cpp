#include "slicer/plan.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/bead.hpp"
#include "core/error.hpp"
#include "core/units.hpp"
#include "slicer/polygons.hpp"
#include "slicer/slice.hpp"

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

class LayerBuilder {
 public:
  LayerBuilder(Toolpath& tp, const SectionParams& s, int section, int layer, double z, Eigen::Vector2d& head)
      : tp_(tp), s_(s), section_(section), layer_(layer), z_(z), head_(head) {
    area_ = bead_area_mm2(s.bead_width_mm, s.layer_height_mm);
  }

  void travel_to(const Eigen::Vector2d& p) {
    Move m = base(Feature::kTravel);
    m.kind = MoveKind::kTravel;
    // From wherever the head really is (the previous layer's height on a layer change).
    m.start = tp_.moves.empty() ? Eigen::Vector3d(head_.x(), head_.y(), z_) : tp_.moves.back().end;
    m.end = {p.x(), p.y(), z_};
    if ((m.end - m.start).norm() < 1e-9) return;
    m.feed_mm_s = s_.travel_speed_mm_s;
    tp_.moves.push_back(m);
    head_ = p;
  }

  void event(ExtruderEvent e) {
    Move m = base(Feature::kUnknown);
    m.kind = MoveKind::kDwell;
    m.event = e;
    m.start = m.end = {head_.x(), head_.y(), z_};
    tp_.moves.push_back(m);
  }

  // Prints along `points` (closed adds the segment back to the start), melt on before and off after.
  void print(const std::vector<Eigen::Vector2d>& points, bool closed, Feature feature, int pass) {
    if (points.size() < 2) return;
    travel_to(points.front());
    event(ExtruderEvent::kMeltOn);
    const std::size_t n = points.size();
    const std::size_t segments = closed ? n : n - 1;
    for (std::size_t i = 0; i < segments; ++i) print_segment(points[(i + 1) % n], feature, pass);
    event(ExtruderEvent::kMeltOff);
  }

  void print_segment(const Eigen::Vector2d& to, Feature feature, int pass) {
    const double len = (to - head_).norm();
    if (len < 1e-6) return;
    Move m = base(feature);
    m.kind = MoveKind::kPrint;
    m.pass = pass;
    m.roller_down = true;
    m.start = {head_.x(), head_.y(), z_};
    m.end = {to.x(), to.y(), z_};
    m.feed_mm_s = s_.print_speed_mm_s;
    m.volume_mm3 = area_ * len;
    tp_.moves.push_back(m);
    head_ = to;
  }

  const Eigen::Vector2d& head() const { return head_; }

 private:
  Move base(Feature feature) const {
    Move m;
    m.feature = feature;
    m.section = section_;
    m.layer = layer_;
    m.bead_width_mm = s_.bead_width_mm;
    m.layer_height_mm = s_.layer_height_mm;
    return m;
  }

  Toolpath& tp_;
  const SectionParams& s_;
  int section_, layer_;
  double z_;
  Eigen::Vector2d& head_;
  double area_ = 0.0;
};

// Rotates a closed contour so it starts at the vertex nearest `near` (the seam follows the head).
Polygon start_near(Polygon poly, const Eigen::Vector2d& near) {
  std::size_t best = 0;
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const double d = (poly[i] - near).squaredNorm();
    if (d < best_d) {
      best_d = d;
      best = i;
    }
  }
  std::rotate(poly.begin(), poly.begin() + static_cast<std::ptrdiff_t>(best), poly.end());
  return poly;
}

void plan_layer(const TriangleMesh& mesh, const SectionParams& s, int section, int layer_in_section,
                Toolpath& tp, Eigen::Vector2d& head, PlanStats& stats) {
  const double z_top = s.z_min_mm + (layer_in_section + 1) * s.layer_height_mm;
  SliceStats slice_stats;
  const Polygons region = slice_mesh(mesh, z_top - 0.5 * s.layer_height_mm, &slice_stats);
  stats.open_chains += slice_stats.open_chains;
  if (region.empty()) {
    ++stats.empty_layers;
    return;
  }
  const int layer = static_cast<int>(tp.layers.size());
  ToolpathLayer info;
  info.z_mm = z_top;
  info.height_mm = s.layer_height_mm;
  info.section = section;
  info.outline_area_mm2 = area_mm2(region);
  info.outline_perimeter_mm = perimeter_mm(region);
  tp.layers.push_back(info);

  const double w = s.bead_width_mm;
  const double pitch = w * (1.0 - s.boundary.overlap);
  LayerBuilder b(tp, s, section, layer, z_top, head);

  // Boundary passes: pass k runs along the outline offset inward by w/2 + k·pitch.
  std::vector<Polygons> passes;
  for (int k = 0; k < s.boundary.passes; ++k) {
    Polygons loops = offset(region, -(0.5 * w + k * pitch));
    if (loops.empty()) break;
    passes.push_back(std::move(loops));
  }
  const int laid = static_cast<int>(passes.size());
  for (int i = 0; i < laid; ++i) {
    const int k = s.boundary.inside_out ? laid - 1 - i : i;
    for (const Polygon& loop : passes[static_cast<std::size_t>(k)])
      b.print(start_near(loop, b.head()), true, Feature::kBoundary, k);
  }

  if (!s.fill.enabled) return;
  // The fill's bead centres stay w/2 − overlap·w inside the last boundary bead's inner edge, which works out
  // to the offset the next boundary pass would have had.
  const double fill_pitch = w * (1.0 - s.fill.overlap);
  const Polygons fill_region = offset(region, -(0.5 * w + laid * pitch));
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

void validate(const std::vector<SectionParams>& sections) {
  for (const auto& s : sections) {
    const std::string key = "sections." + s.name;
    if (!(s.layer_height_mm > 0)) throw InputError({}, key + ".layer_height", "must be positive");
    if (!(s.bead_width_mm >= s.layer_height_mm))
      throw InputError({}, key + ".bead_width",
                       fmt::format("must be at least the layer height ({} mm), got {} mm", s.layer_height_mm,
                                   s.bead_width_mm));
    if (!(s.z_max_mm > s.z_min_mm))
      throw InputError({}, key + ".z", "upper limit must be above the lower one");
    if (!(s.print_speed_mm_s > 0)) throw InputError({}, key + ".speed", "must be positive");
    if (s.boundary.passes < 0) throw InputError({}, key + ".boundary.passes", "must not be negative");
    if (!(s.boundary.overlap >= 0 && s.boundary.overlap < 0.5))
      throw InputError({}, key + ".boundary.overlap", "must be in [0, 50 %)");
    if (!(s.fill.overlap >= 0 && s.fill.overlap < 0.5))
      throw InputError({}, key + ".fill.overlap", "must be in [0, 50 %)");
  }
}

}  // namespace

Toolpath plan_toolpath(const TriangleMesh& mesh, const std::vector<SectionParams>& sections,
                       const MotionLimits& motion, PlanStats* stats) {
  validate(sections);
  std::vector<std::size_t> order(sections.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return sections[a].z_min_mm < sections[b].z_min_mm; });
  Toolpath tp;
  for (const auto& s : sections) tp.sections.push_back(s.name);
  PlanStats local;
  Eigen::Vector2d head(mesh.min_corner().x(), mesh.min_corner().y());
  for (const std::size_t si : order) {
    const SectionParams& s = sections[si];
    const int layers = static_cast<int>(std::floor((s.z_max_mm - s.z_min_mm) / s.layer_height_mm + 1e-6));
    for (int l = 0; l < layers; ++l) plan_layer(mesh, s, static_cast<int>(si), l, tp, head, local);
  }
  time_toolpath(tp, motion);
  if (stats) *stats = local;
  return tp;
}

}  // namespace beadtwin::slicer
