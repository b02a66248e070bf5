#include "slicer/polygons.hpp"

#include <algorithm>
#include <cmath>

#include <clipper.hpp>

namespace beadtwin::slicer {
namespace {

// Clipper works on integers: 1 unit = 1 µm, enough for 3 m parts with room to spare in 64 bits.
constexpr double kScale = 1000.0;

ClipperLib::IntPoint to_int(const Eigen::Vector2d& p) {
  return {static_cast<ClipperLib::cInt>(std::llround(p.x() * kScale)),
          static_cast<ClipperLib::cInt>(std::llround(p.y() * kScale))};
}
Eigen::Vector2d to_mm(const ClipperLib::IntPoint& p) {
  return {static_cast<double>(p.X) / kScale, static_cast<double>(p.Y) / kScale};
}

ClipperLib::Paths to_paths(const std::vector<std::vector<Eigen::Vector2d>>& in) {
  ClipperLib::Paths out;
  out.reserve(in.size());
  for (const auto& poly : in) {
    ClipperLib::Path path;
    path.reserve(poly.size());
    for (const auto& p : poly) path.push_back(to_int(p));
    out.push_back(std::move(path));
  }
  return out;
}

Polygons to_polygons(const ClipperLib::Paths& in) {
  Polygons out;
  out.reserve(in.size());
  for (const auto& path : in) {
    if (path.size() < 2) continue;
    Polygon poly;
    poly.reserve(path.size());
    for (const auto& p : path) poly.push_back(to_mm(p));
    out.push_back(std::move(poly));
  }
  return out;
}

}  // namespace

double area_mm2(const Polygons& polygons) {
  double a = 0.0;
  for (const auto& poly : polygons) {
    for (std::size_t i = 0, n = poly.size(); i < n; ++i) {
      const auto& p = poly[i];
      const auto& q = poly[(i + 1) % n];
      a += p.x() * q.y() - q.x() * p.y();
    }
  }
  return 0.5 * a;
}

double perimeter_mm(const Polygons& polygons) {
  double l = 0.0;
  for (const auto& poly : polygons)
    for (std::size_t i = 0, n = poly.size(); i < n; ++i) l += (poly[(i + 1) % n] - poly[i]).norm();
  return l;
}

Polygons offset(const Polygons& polygons, double delta_mm) {
  // Miter limit 2: corners down to about 60 degrees stay sharp; the arc tolerance (5 µm) applies to curves.
  ClipperLib::ClipperOffset co(2.0, 0.005 * kScale);
  co.AddPaths(to_paths(polygons), ClipperLib::jtMiter, ClipperLib::etClosedPolygon);
  ClipperLib::Paths out;
  co.Execute(out, delta_mm * kScale);
  return to_polygons(out);
}

Polygons offset_round(const Polygons& polygons, double delta_mm, double arc_tolerance_mm) {
  ClipperLib::ClipperOffset co(2.0, std::max(arc_tolerance_mm, 0.001) * kScale);
  co.AddPaths(to_paths(polygons), ClipperLib::jtRound, ClipperLib::etClosedPolygon);
  ClipperLib::Paths out;
  co.Execute(out, delta_mm * kScale);
  return to_polygons(out);
}

Polygons sweep(const std::vector<Polyline>& paths, double width_mm) {
  ClipperLib::ClipperOffset co(2.0, 0.005 * kScale);
  for (const Polyline& path : paths) {
    if (path.size() < 2) continue;
    const bool closed = path.size() > 2 && (path.front() - path.back()).norm() < 1e-6;
    co.AddPaths(to_paths({closed ? Polyline(path.begin(), path.end() - 1) : path}), ClipperLib::jtRound,
                closed ? ClipperLib::etClosedLine : ClipperLib::etOpenButt);
  }
  ClipperLib::Paths out;
  co.Execute(out, 0.5 * width_mm * kScale);
  return to_polygons(out);
}

Polygons union_nonzero(const Polygons& loops) {
  ClipperLib::Clipper c;
  c.AddPaths(to_paths(loops), ClipperLib::ptSubject, true);
  ClipperLib::Paths out;
  c.Execute(ClipperLib::ctUnion, out, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  return to_polygons(out);
}

namespace {

// Marks the points of poly[first..last] to keep, Ramer-Douglas-Peucker.
void rdp(const Polygon& poly, std::size_t first, std::size_t last, double tol, std::vector<bool>& keep) {
  double worst = -1.0;
  std::size_t at = first;
  for (std::size_t i = first + 1; i < last; ++i) {
    const double d = distance_to_segment(poly[i], poly[first], poly[last]);
    if (d > worst) worst = d, at = i;
  }
  if (worst > tol) {
    keep[at] = true;
    rdp(poly, first, at, tol, keep);
    rdp(poly, at, last, tol, keep);
  }
}

}  // namespace

namespace {

// Turn (radians, unsigned) at point b between the segments a→b and b→c.
double turn_at(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const Eigen::Vector2d u = b - a, v = c - b;
  return std::abs(turn_rad(u, v));
}

// Puts original points back (the middle one of a skipped run) next to kept points where the simplified
// contour turns much more sharply than the original did there.
void keep_curves_smooth(const Polygon& closed, std::vector<bool>& keep) {
  const double limit = kSmoothTurnDeg * 3.14159265358979323846 / 180.0;
  const std::size_t n = closed.size() - 1;  // closed.back() repeats closed.front()
  for (bool changed = true; changed;) {
    changed = false;
    std::vector<std::size_t> kept;
    for (std::size_t i = 0; i < n; ++i)
      if (keep[i]) kept.push_back(i);
    const std::size_t m = kept.size();
    if (m < 3) return;
    for (std::size_t k = 0; k < m; ++k) {
      const std::size_t prev = kept[(k + m - 1) % m], at = kept[k], next = kept[(k + 1) % m];
      const double simplified = turn_at(closed[prev], closed[at], closed[next]);
      const double original = turn_at(closed[(at + n - 1) % n], closed[at], closed[(at + 1) % n]);
      if (simplified <= limit || simplified <= 1.5 * original) continue;
      // The middles of the skipped runs on both sides, when there are points to put back.
      const std::size_t before = prev < at ? at - prev : at + n - prev;
      const std::size_t after = at < next ? next - at : next + n - at;
      if (before > 1) keep[(prev + before / 2) % n] = changed = true;
      if (after > 1) keep[(at + after / 2) % n] = changed = true;
    }
  }
}

}  // namespace

Polygons simplify(const Polygons& polygons, double tolerance_mm, bool smooth_curves) {
  if (tolerance_mm <= 0) return polygons;
  Polygons out;
  for (const Polygon& poly : polygons) {
    if (poly.size() < 4) {
      out.push_back(poly);
      continue;
    }
    // Split the closed contour at its first point and the point farthest from it, and simplify both halves.
    std::size_t far = 0;
    for (std::size_t i = 1; i < poly.size(); ++i)
      if ((poly[i] - poly[0]).squaredNorm() > (poly[far] - poly[0]).squaredNorm()) far = i;
    Polygon closed = poly;
    closed.push_back(poly.front());
    std::vector<bool> keep(closed.size(), false);
    keep[0] = keep[far] = keep.back() = true;
    rdp(closed, 0, far, tolerance_mm, keep);
    rdp(closed, far, closed.size() - 1, tolerance_mm, keep);
    if (smooth_curves) keep_curves_smooth(closed, keep);
    Polygon simple;
    for (std::size_t i = 0; i + 1 < closed.size(); ++i)
      if (keep[i]) simple.push_back(closed[i]);
    if (simple.size() >= 3) out.push_back(std::move(simple));
  }
  return out;
}

Polygons drop_small(const Polygons& polygons, double min_area_mm2) {
  if (min_area_mm2 <= 0) return polygons;
  Polygons out;
  for (const Polygon& poly : polygons)
    if (std::abs(area_mm2({poly})) >= min_area_mm2) out.push_back(poly);
  return out;
}

namespace {

Polygons boolean(ClipperLib::ClipType op, const Polygons& a, const Polygons& b) {
  ClipperLib::Clipper c;
  c.AddPaths(to_paths(a), ClipperLib::ptSubject, true);
  c.AddPaths(to_paths(b), ClipperLib::ptClip, true);
  ClipperLib::Paths out;
  c.Execute(op, out, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  return to_polygons(out);
}

}  // namespace

Polygons difference(const Polygons& a, const Polygons& b) {
  return boolean(ClipperLib::ctDifference, a, b);
}
Polygons intersection(const Polygons& a, const Polygons& b) {
  return boolean(ClipperLib::ctIntersection, a, b);
}
Polygons unite(const Polygons& a, const Polygons& b) {
  return boolean(ClipperLib::ctUnion, a, b);
}

void split_contours(const Polygons& region, Polygons& outers, Polygons& holes) {
  outers.clear();
  holes.clear();
  for (const Polygon& p : region) (area_mm2({p}) >= 0 ? outers : holes).push_back(p);
}

std::vector<Polyline> clip_lines(const std::vector<Polyline>& lines, const Polygons& region, bool inside) {
  ClipperLib::Clipper c;
  c.AddPaths(to_paths(lines), ClipperLib::ptSubject, false);
  c.AddPaths(to_paths(region), ClipperLib::ptClip, true);
  ClipperLib::PolyTree tree;
  c.Execute(inside ? ClipperLib::ctIntersection : ClipperLib::ctDifference, tree, ClipperLib::pftNonZero,
            ClipperLib::pftNonZero);
  ClipperLib::Paths open;
  ClipperLib::OpenPathsFromPolyTree(tree, open);
  std::vector<Polyline> out;
  for (const auto& path : open) {
    Polyline line;
    for (const auto& p : path) line.push_back(to_mm(p));
    if (line.size() >= 2) out.push_back(std::move(line));
  }
  return out;
}

bool contains(const Polygons& region, const Eigen::Vector2d& p) {
  const ClipperLib::IntPoint ip = to_int(p);
  int winding = 0;
  for (const auto& poly : region) {
    ClipperLib::Path path;
    for (const auto& q : poly) path.push_back(to_int(q));
    if (ClipperLib::PointInPolygon(ip, path) != 0) winding += ClipperLib::Orientation(path) ? 1 : -1;
  }
  return winding > 0;
}

}  // namespace beadtwin::slicer
