#include "slicer/plan.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>

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
  // `role` marks every printed move of the layer (kRaft, kStockOnTop); kUnknown keeps each move's own.
  LayerBuilder(Toolpath& tp, const SectionParams& s, int section, int layer, double z, Eigen::Vector2d& head,
               Feature role)
      : tp_(tp), s_(s), section_(section), layer_(layer), z_(z), head_(head), role_(role) {
    area_ = bead_area_mm2(s.bead_width_mm, s.layer_height_mm);
  }

  void travel_to(const Eigen::Vector2d& p) {
    Move m = base(Feature::kTravel);
    m.kind = MoveKind::kTravel;
    // From wherever the head really is (the previous layer's height on a layer change).
    // The program starts with the head at the initial clearance height (patent (45)), if one is set.
    m.start = tp_.moves.empty()
                  ? Eigen::Vector3d(head_.x(), head_.y(), std::max(z_, s_.initial_clearance_height_mm))
                  : tp_.moves.back().end;
    m.feed_mm_s = s_.travel_speed_mm_s;
    if (m.start.z() > z_ + 1e-9 && (p - m.start.head<2>()).norm() > 1e-9) {
      // Raised (clearance height): across at that height first, then straight down.
      m.end = {p.x(), p.y(), m.start.z()};
      tp_.moves.push_back(m);
      m.start = m.end;
    }
    m.end = {p.x(), p.y(), z_};
    head_ = p;
    if ((m.end - m.start).norm() < 1e-9) return;
    tp_.moves.push_back(m);
  }

  void event(ExtruderEvent e) {
    Move m = base(Feature::kUnknown);
    m.kind = MoveKind::kDwell;
    m.event = e;
    m.start = m.end = {head_.x(), head_.y(), z_};
    tp_.moves.push_back(m);
  }

  // A closed boundary pass with its lead-in (a straight approach along the first segment's line, ending at
  // the start) and lead-out (a straight run-off along the last segment's direction), both printed.
  // `overlap_mm` runs the pass on past its start (start/stop overlap) before the lead-out.
  void print_pass(const Polygon& loop, int pass, double lead_in_mm, double lead_out_mm, double overlap_mm,
                  bool tangential_lead_out) {
    if (loop.size() < 2) return;
    const Eigen::Vector2d first_dir = (loop[1] - loop[0]).normalized();
    travel_to(loop.front() - lead_in_mm * first_dir);
    event(ExtruderEvent::kMeltOn);
    if (lead_in_mm > 0) print_segment(loop.front(), Feature::kLeadIn, pass);
    for (std::size_t i = 1; i <= loop.size(); ++i)
      print_segment(loop[i % loop.size()], Feature::kBoundary, pass);
    // Start/stop overlap, then (unless the lead-out is tangential) the lead-out: on along the contour again,
    // retracing the bead just laid, so the pump slows by the melt setting (patent (46)).
    const double flow = 1.0 - s_.melt_reduction;
    const std::size_t next = run_along(loop, 1, overlap_mm, Feature::kBoundary, pass, flow);
    if (!tangential_lead_out) run_along(loop, next, lead_out_mm, Feature::kLeadOut, pass, flow);
    if (tangential_lead_out && lead_out_mm > 0 && tp_.moves.back().kind == MoveKind::kPrint) {
      const Move& last = tp_.moves.back();
      const Eigen::Vector2d dir = (last.end - last.start).head<2>().normalized();
      print_segment(head_ + lead_out_mm * dir, Feature::kLeadOut, pass);
    }
    event(ExtruderEvent::kMeltOff);
  }

  // Prints on along the closed `loop` from the head, which lies on the segment ending at loop[next], for
  // `length_mm`; returns the index of the next corner ahead.
  std::size_t run_along(const Polygon& loop, std::size_t next, double length_mm, Feature feature, int pass,
                        double flow) {
    // A bound on the laps, in case the loop is (nearly) a point.
    for (std::size_t guard = 0; length_mm > 1e-9 && guard < 4 * loop.size(); ++guard) {
      const Eigen::Vector2d to = loop[next % loop.size()];
      const double len = (to - head_).norm();
      if (len > length_mm) {
        print_segment(head_ + (to - head_) * (length_mm / len), feature, pass, flow);
        break;
      }
      print_segment(to, feature, pass, flow);
      length_mm -= len;
      next = (next + 1) % loop.size();
    }
    return next;
  }

  // An open path (AM Outline) with its lead-in along the first segment and its lead-out along the last.
  void print_open(const Polyline& path, int pass, double lead_in_mm, double lead_out_mm) {
    if (path.size() < 2) return;
    const Eigen::Vector2d first_dir = (path[1] - path[0]).normalized();
    travel_to(path.front() - lead_in_mm * first_dir);
    event(ExtruderEvent::kMeltOn);
    if (lead_in_mm > 0) print_segment(path.front(), Feature::kLeadIn, pass);
    for (std::size_t i = 1; i < path.size(); ++i) print_segment(path[i], Feature::kBoundary, pass);
    if (lead_out_mm > 0)
      print_segment(head_ + lead_out_mm * (path.back() - path[path.size() - 2]).normalized(),
                    Feature::kLeadOut, pass);
    event(ExtruderEvent::kMeltOff);
  }

  // One bead of its own width (a thin wall's); at least as wide as the layer is high.
  void print_thin(const Eigen::Vector2d& to, double width_mm) {
    const double w = std::max(width_mm, s_.layer_height_mm);
    const std::size_t before = tp_.moves.size();
    print_segment(to, Feature::kThinWall, -1, bead_area_mm2(w, s_.layer_height_mm) / area_);
    if (tp_.moves.size() > before) tp_.moves.back().bead_width_mm = w;
  }

  // `flow` scales the material (the melt setting's pump reduction where a bead is laid over another).
  void print_segment(const Eigen::Vector2d& to, Feature feature, int pass, double flow = 1.0) {
    const double len = (to - head_).norm();
    if (len < 1e-6) return;
    Move m = base(feature);
    m.kind = MoveKind::kPrint;
    m.pass = pass;
    m.roller_down = true;
    m.start = {head_.x(), head_.y(), z_};
    m.end = {to.x(), to.y(), z_};
    m.feed_mm_s = s_.print_speed_mm_s;
    m.volume_mm3 = area_ * len * flow;
    tp_.moves.push_back(m);
    head_ = to;
  }

  const Eigen::Vector2d& head() const { return head_; }

 private:
  Move base(Feature feature) const {
    Move m;
    m.feature = role_ != Feature::kUnknown && feature != Feature::kTravel && feature != Feature::kUnknown
                    ? role_
                    : feature;
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
  Feature role_;
  double area_ = 0.0;
};

// Rotates a closed contour so it starts at the point nearest `near`, moved `advance_mm` further along the
// contour in its own direction (the seam avoidance offset); the start becomes a vertex if it is not one.
Polygon start_at(const Polygon& poly, const Eigen::Vector2d& near, double advance_mm) {
  const std::size_t n = poly.size();
  // Nearest point on the contour, as (segment, parameter).
  std::size_t seg = 0;
  double t_best = 0.0, d_best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d a = poly[i], d = poly[(i + 1) % n] - a;
    const double len2 = d.squaredNorm();
    const double t = len2 > 0 ? std::clamp((near - a).dot(d) / len2, 0.0, 1.0) : 0.0;
    const double dist = (a + t * d - near).squaredNorm();
    if (dist < d_best) d_best = dist, seg = i, t_best = t;
  }
  // Walk `advance_mm` along the contour (modulo its length).
  const double perimeter = perimeter_mm({poly});
  double left = perimeter > 0 ? std::fmod(std::max(0.0, advance_mm), perimeter) : 0.0;
  double t = t_best;
  for (std::size_t guard = 0; guard <= n; ++guard) {
    const double len = (poly[(seg + 1) % n] - poly[seg]).norm();
    const double room = (1.0 - t) * len;
    if (left <= room || len == 0.0) {
      if (len > 0) t += left / len;
      break;
    }
    left -= room;
    seg = (seg + 1) % n;
    t = 0.0;
  }
  const Eigen::Vector2d start = poly[seg] + t * (poly[(seg + 1) % n] - poly[seg]);
  Polygon out;
  out.reserve(n + 1);
  out.push_back(start);
  for (std::size_t k = 1; k <= n; ++k) {
    const Eigen::Vector2d& p = poly[(seg + k) % n];
    if ((p - out.back()).squaredNorm() > 1e-12 && (k < n || (p - start).squaredNorm() > 1e-12))
      out.push_back(p);
  }
  return out;
}

// The region a layer of section `s` fills at height `z_mid`, after the toolpath parameters that change it.
Polygons layer_region(const TriangleMesh& mesh, const SectionParams& s, double z_mid, PlanStats& stats) {
  SliceStats slice_stats;
  Polygons region = slice_mesh(mesh, z_mid, &slice_stats);
  stats.open_chains += slice_stats.open_chains;
  if (s.merge_slices) {
    // Merge slices for extra stock: the largest outline of the previous, this and the next layer.
    for (const double dz : {-s.layer_height_mm, s.layer_height_mm}) {
      Polygons other = slice_mesh(mesh, z_mid + dz);
      if (area_mm2(other) > area_mm2(region)) region = std::move(other);
    }
  }
  region = drop_small(simplify(region, s.chord_tolerance_mm), s.min_polygon_area_mm2);
  if (s.shift_mm != Eigen::Vector2d::Zero())
    for (Polygon& poly : region)
      for (Eigen::Vector2d& p : poly) p += s.shift_mm;
  Polygons outers, holes;
  split_contours(region, outers, holes);
  if (s.ignore_inner_contours) holes.clear();
  if (s.outer_stock_mm != 0.0) outers = offset(outers, s.outer_stock_mm);
  if (!holes.empty()) {
    // Holes as regions of their own (counter-clockwise), shrunk by the inner stock, cut out of the outers.
    for (Polygon& h : holes) std::reverse(h.begin(), h.end());
    if (s.inner_stock_mm != 0.0) holes = offset(holes, -s.inner_stock_mm);
    return difference(outers, holes);
  }
  return union_nonzero(outers);
}

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

// One layer: the boundary passes and (where enabled, or forced for rafts) the fill, in the section's layer
// order. `role` marks raft and stock-on-top layers. `angle_index` turns the fill and moves the seam.
void lay_layer(Toolpath& tp, const SectionParams& s, int section, const Polygons& region, double z_top,
               int angle_index, Feature role, bool fill, Eigen::Vector2d& head) {
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
  if (s.clearance_height_mm > 0 && !tp.moves.empty()) {
    // Clearance between layers: straight up, then across at the clearance height.
    const double zc = std::max(s.clearance_height_mm, z_top);
    const Eigen::Vector3d from = tp.moves.back().end;
    Move up;
    up.kind = MoveKind::kTravel;
    up.feature = Feature::kTravel;
    up.section = section;
    up.layer = layer;
    up.feed_mm_s = s.travel_speed_mm_s;
    up.start = from;
    up.end = {from.x(), from.y(), std::max(zc, from.z())};
    if ((up.end - up.start).norm() > 1e-9) tp.moves.push_back(up);
  }
  LayerBuilder b(tp, s, section, layer, z_top, head, role);

  // Boundary passes: pass k runs along the outline offset inward by w/2 + k·pitch.
  std::vector<Polygons> passes;
  for (int k = 0; k < s.boundary.passes; ++k) {
    Polygons loops = offset(region, -(0.5 * w + k * pitch));
    if (loops.empty()) break;
    passes.push_back(std::move(loops));
  }
  // The fill's bead centres stay w/2 − overlap·w inside the last boundary bead's inner edge, which works out
  // to the offset the next boundary pass would have had.
  const Polygons fill_region =
      fill ? offset(region, -(0.5 * w + static_cast<double>(passes.size()) * pitch)) : Polygons{};
  if (s.fill_first) lay_fill(b, s, fill_region, angle_index);
  lay_boundary(b, s, passes, angle_index);
  if (s.boundary.thin_walls) lay_thin_walls(b, s, region);
  if (!s.fill_first) lay_fill(b, s, fill_region, angle_index);
}

// One layer to lay: where, for which section, with what outline and role.
struct LayerJob {
  double z_top_mm = 0.0;
  int section = 0;
  int order = 0;  // the section's place in Z order: breaks ties at equal heights
  Polygons region;
  int angle_index = 0;  // layers laid before it in its section: turns the fill and moves the seam
  Feature role = Feature::kUnknown;
  bool fill = false;
  bool outline = false;  // an AM Outline layer: the section's own path, not a slice
};

// Every layer of one section, with its rafts below and its stock on top, shifted up by `z_shift_mm`.
void section_jobs(const TriangleMesh& mesh, const SectionParams& s, int section, int order, double z_shift_mm,
                  std::vector<LayerJob>& jobs, PlanStats& stats) {
  const int layers = static_cast<int>(std::floor((s.z_max_mm - s.z_min_mm) / s.layer_height_mm + 1e-6));
  const double h = s.layer_height_mm;
  int index = 0;
  std::optional<std::size_t> last_at;  // the section's top layer among the jobs
  for (int l = 0; l < layers; ++l) {
    const double z_cad = s.z_min_mm + (l + 1) * h;
    Polygons region = layer_region(mesh, s, z_cad - 0.5 * h, stats);
    if (region.empty()) {
      ++stats.empty_layers;
      continue;
    }
    if (index == 0) {
      // Rafts: solid layers with the first layer's outline; the part sits on them (z_shift_mm includes them).
      for (int r = 0; r < s.rafts; ++r)
        jobs.push_back(
            {z_cad - (s.rafts - r) * h + z_shift_mm, section, order, region, index++, Feature::kRaft, true});
    }
    jobs.push_back(
        {z_cad + z_shift_mm, section, order, std::move(region), index++, Feature::kUnknown, s.fill.enabled});
    last_at = jobs.size() - 1;
  }
  // Stock on top: solid layers on the section's top layer, with its outline.
  if (!last_at) return;
  const Polygons top = jobs[*last_at].region;
  const double top_z = jobs[*last_at].z_top_mm;
  for (int t = 0; t < s.stock_on_top; ++t)
    jobs.push_back({top_z + (t + 1) * h, section, order, top, index++, Feature::kStockOnTop, true});
}

// AM Outline: every layer of the section prints its 2-D path (patent (39)).
void outline_jobs(const SectionParams& s, int section, int order, double z_shift_mm,
                  std::vector<LayerJob>& jobs) {
  const int layers = static_cast<int>(std::floor((s.z_max_mm - s.z_min_mm) / s.layer_height_mm + 1e-6));
  for (int l = 0; l < layers; ++l) {
    LayerJob j;
    j.z_top_mm = s.z_min_mm + (l + 1) * s.layer_height_mm + z_shift_mm;
    j.section = section;
    j.order = order;
    j.angle_index = l;
    j.outline = true;
    jobs.push_back(std::move(j));
  }
}

void lay_outline(Toolpath& tp, const SectionParams& s, int section, double z_top, int index,
                 Eigen::Vector2d& head) {
  Polygon path = s.outline_path;
  for (Eigen::Vector2d& p : path) p += s.shift_mm;
  const double length =
      s.outline_closed ? perimeter_mm({path}) : perimeter_mm({path}) - (path.back() - path.front()).norm();
  ToolpathLayer info;
  info.z_mm = z_top;
  info.height_mm = s.layer_height_mm;
  info.section = section;
  info.outline_area_mm2 = length * s.bead_width_mm;  // the bead's footprint
  info.outline_perimeter_mm = 2.0 * length;
  const int layer = static_cast<int>(tp.layers.size());
  tp.layers.push_back(info);
  LayerBuilder b(tp, s, section, layer, z_top, head, Feature::kUnknown);
  if (s.boundary.reverse_alternate && index % 2 == 1) std::reverse(path.begin(), path.end());
  if (s.outline_closed) {
    b.print_pass(start_at(path, s.start_point_mm, index * s.seam_offset_mm), 0, s.boundary.lead_in_mm,
                 s.boundary.lead_out_mm, s.boundary.start_stop_overlap * s.bead_width_mm,
                 s.boundary.tangential_lead_out);
    return;
  }
  // Open toolpath start (patent (43)): from whichever end is nearer the start point (before the alternating
  // reversal, which then runs every other layer back).
  const bool from_far_end =
      (s.outline_path.back() - s.start_point_mm).norm() < (s.outline_path.front() - s.start_point_mm).norm();
  if (from_far_end) std::reverse(path.begin(), path.end());
  b.print_open(path, 0, s.boundary.lead_in_mm, s.boundary.lead_out_mm);
}

// The mesh a section slices: the whole part, or the one body it names.
TriangleMesh section_mesh(const TriangleMesh& mesh, const SectionParams& s) {
  if (s.body.empty()) return mesh;
  const int body = find_body(mesh, s.body);
  if (body < 0)
    throw InputError(
        {}, "sections." + s.name + ".body",
        fmt::format("the part has no body named '{}'; its bodies are: {}", s.body, body_list(mesh)));
  return select_body(mesh, body);
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
  if (sections.empty()) throw InputError({}, "sections", "there is no section to plan");
  for (std::size_t i = 1; i < order.size(); ++i)
    if (sections[order[i]].rafts > 0)
      throw InputError({}, "sections." + sections[order[i]].name + ".rafts",
                       "rafts go under the lowest section only (they lift the whole part)");
  Toolpath tp;
  for (const auto& s : sections) tp.sections.push_back(s.name);
  PlanStats local;
  Eigen::Vector2d head = mesh.vertices.empty()
                             ? Eigen::Vector2d::Zero()
                             : Eigen::Vector2d(mesh.min_corner().x(), mesh.min_corner().y());
  // Rafts under the lowest section lift the whole part.
  const SectionParams& lowest = sections[order.front()];
  const double z_shift = lowest.rafts * lowest.layer_height_mm;
  std::vector<LayerJob> jobs;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const SectionParams& s = sections[order[i]];
    if (!s.outline_path.empty())
      outline_jobs(s, static_cast<int>(order[i]), static_cast<int>(i), z_shift + s.contact_offset_mm, jobs);
    else
      section_jobs(section_mesh(mesh, s), s, static_cast<int>(order[i]), static_cast<int>(i),
                   z_shift + s.contact_offset_mm, jobs, local);
  }
  // AM Z merge (patent (14), (39)): the layers of all sections in one program, by height, so sections side
  // by side rise together and an elevated section starts when the build reaches it (patent (16)).
  std::stable_sort(jobs.begin(), jobs.end(), [](const LayerJob& a, const LayerJob& b) {
    if (std::abs(a.z_top_mm - b.z_top_mm) > 1e-9) return a.z_top_mm < b.z_top_mm;
    return a.order < b.order;
  });
  for (const LayerJob& j : jobs) {
    if (j.outline) {
      lay_outline(tp, sections[static_cast<std::size_t>(j.section)], j.section, j.z_top_mm, j.angle_index,
                  head);
      continue;
    }
    lay_layer(tp, sections[static_cast<std::size_t>(j.section)], j.section, j.region, j.z_top_mm,
              j.angle_index, j.role, j.fill, head);
  }
  time_toolpath(tp, motion);
  if (stats) *stats = local;
  return tp;
}

}  // namespace beadtwin::slicer
