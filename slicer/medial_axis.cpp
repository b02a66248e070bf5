// The medial axis comes from the Voronoi diagram of the outline's segments. We build that diagram with
// Boost.Polygon's voronoi (header-only) because it is a well-kept, robust segment Voronoi: its predicates
// are exact on integer input, so near-degenerate outlines (parallel walls, cocircular corners) give a
// consistent diagram instead of a crash. Its price is int32 input, hence the integer frame below, and
// segments that meet only at their ends, hence the clean-up of the outline first.
//
// From the diagram we keep the primary edges inside the region (not the secondary ones, between a segment
// and its own end point) across which the outline faces itself, which leaves out the branches running into
// blunt convex corners. We cut each edge where its width leaves the asked range and chain the pieces
// through the vertices where exactly two of them meet.
#include "slicer/medial_axis.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <optional>
#include <string>
#include <utility>

#include <clipper.hpp>

#include <boost/polygon/polygon.hpp>  // before segment_utils.hpp, which needs it but does not include it
#include <boost/polygon/segment_utils.hpp>
#include <boost/polygon/voronoi.hpp>

#include "core/error.hpp"
#include "core/geometry.hpp"

namespace beadtwin::slicer {
namespace {

namespace bp = boost::polygon;
using Diagram = bp::voronoi_diagram<double>;
using Vec = Eigen::Vector2d;

// 1 unit = 1 µm, as for Clipper in polygons.cpp. Boost takes int32 coordinates; measured from the middle of
// the region, 2^30 units (a kilometre each way) leaves a factor two spare. Larger regions get coarser units.
constexpr double kUnitsPerMm = 1000.0;
constexpr double kMaxUnits = 1073741824.0;  // 2^30
// Points nearer the outline than this (units) are on it.
constexpr double kOnOutline = 1e-3;
// Slack on the width limits (units), so a wall exactly as wide as a limit is not lost to rounding.
constexpr double kWidthSlack = 1e-6;
// Edges shorter than this (units) are where Boost splits a degenerate vertex (four or more sites on one
// circle) into two: their ends are one junction.
constexpr double kSameVertex = 1e-3;
// Curved edges are split until the polyline is within this fraction of the local width of the curve, and
// the width linear between samples to the same tolerance; no finer than kMinCurveTolerance (units), and
// at most kMaxSplits halvings deep.
constexpr double kCurveTolerance = 0.005;
constexpr double kMinCurveTolerance = 1e-3;
constexpr int kMaxSplits = 20;
// An edge is kept where the outline points nearest it face each other across it: somewhere along it they
// make at least this angle at the edge. Across a wall with parallel sides it is 180°; where the wall bends
// round a chamfer it stays above 135°; on the branch into a corner of angle α it is 180° − α, so the
// branches into square and blunter corners go, and those into corners sharper than 70° (a wall narrowing
// to a point) stay.
constexpr double kMinFacingAngleRad = 110.0 * std::numbers::pi / 180.0;

double cross(const Vec& a, const Vec& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Units = (mm - origin) · scale.
struct Frame {
  Vec origin = Vec::Zero();  // whole mm, so the grid is the same 1 µm grid wherever the region lies
  double scale = kUnitsPerMm;
};

Frame frame_for(const Polygons& region) {
  Vec lo = Vec::Constant(std::numeric_limits<double>::infinity());
  Vec hi = -lo;
  for (const Polygon& poly : region)
    for (const Vec& p : poly) {
      if (!p.allFinite())
        throw InternalError("medial_axis: outline point is not finite (" + std::to_string(p.x()) + ", " +
                            std::to_string(p.y()) + ")");
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  Frame f;
  if (!(lo.x() <= hi.x())) return f;  // no points
  f.origin = (0.5 * (lo + hi)).array().round().matrix();
  const double reach = std::max((hi - f.origin).cwiseAbs().maxCoeff(), (lo - f.origin).cwiseAbs().maxCoeff());
  if (reach * f.scale > kMaxUnits) f.scale = kMaxUnits / reach;
  return f;
}

using Segment = bp::segment_data<int>;
using Point = bp::point_data<int>;

Vec vec(const Point& p) {
  return {static_cast<double>(p.x()), static_cast<double>(p.y())};
}

// The region's outline on the integer grid as segments with the interior on their left, cleaned so Boost's
// precondition holds (segments meet only at their ends): Clipper merges overlaps and removes crossings,
// repeated and collinear points; Boost's own intersect_segments then splits a segment where another's end
// touches it, which Clipper leaves (a hole touching the outline at a point, say).
struct Outline {
  // A boundary segment leaving or reaching a point, as its direction from the point.
  struct Ray {
    Vec direction;
    bool leaving;  // the region is on its counter-clockwise side if it leaves, on its clockwise side if not
  };
  std::vector<Segment> segments;
  std::map<std::pair<int, int>, std::vector<Ray>> rays;  // at each end point of a segment
};

ClipperLib::Paths merged(const Polygons& region, const Frame& f) {
  ClipperLib::Paths in;
  for (const Polygon& poly : region) {
    ClipperLib::Path path;
    for (const Vec& p : poly) {
      const Vec u = (p - f.origin) * f.scale;
      path.push_back({static_cast<ClipperLib::cInt>(std::llround(u.x())),
                      static_cast<ClipperLib::cInt>(std::llround(u.y()))});
    }
    if (path.size() >= 3) in.push_back(std::move(path));
  }
  ClipperLib::Clipper c;
  c.AddPaths(in, ClipperLib::ptSubject, true);
  ClipperLib::Paths out;
  c.Execute(ClipperLib::ctUnion, out, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  return out;
}

Outline outline_of(const Polygons& region, const Frame& f) {
  std::vector<Segment> joined;
  for (const ClipperLib::Path& path : merged(region, f)) {
    if (path.size() < 3) continue;
    for (std::size_t i = 0; i < path.size(); ++i) {
      const ClipperLib::IntPoint& a = path[i];
      const ClipperLib::IntPoint& b = path[(i + 1) % path.size()];
      joined.emplace_back(Point(static_cast<int>(a.X), static_cast<int>(a.Y)),
                          Point(static_cast<int>(b.X), static_cast<int>(b.Y)));
    }
  }
  std::vector<std::pair<std::size_t, Segment>> split;
  bp::intersect_segments(split, joined.begin(), joined.end());
  Outline o;
  for (const auto& [from, piece] : split) {
    Point a = bp::low(piece), b = bp::high(piece);
    if (a == b) continue;
    // The pieces come out in sweep order: give each its segment's direction back.
    if ((vec(b) - vec(a)).dot(vec(bp::high(joined[from])) - vec(bp::low(joined[from]))) < 0) std::swap(a, b);
    o.segments.emplace_back(a, b);
    o.rays[{a.x(), a.y()}].push_back({vec(b) - vec(a), true});
    o.rays[{b.x(), b.y()}].push_back({vec(a) - vec(b), false});
  }
  return o;
}

// What a Voronoi cell is the cell of: a segment a→b of the outline, or one of its end points (at a).
struct Site {
  bool is_point = false;
  Vec a = Vec::Zero(), b = Vec::Zero();

  double distance(const Vec& p) const { return is_point ? (p - a).norm() : distance_to_segment(p, a, b); }
};

Site site_of(const Diagram::cell_type& cell, const Outline& o) {
  const Segment& seg = o.segments[cell.source_index()];
  Site s;
  s.a = vec(bp::low(seg));
  s.b = vec(bp::high(seg));
  if (cell.contains_point()) {
    s.is_point = true;
    if (cell.source_category() == bp::SOURCE_CATEGORY_SEGMENT_END_POINT) s.a = s.b;
    s.b = s.a;
  }
  return s;
}

// Whether the region lies in direction d from a point of the outline: it does if the first boundary ray
// met turning clockwise from d leaves the point (the region being on a leaving ray's counter-clockwise
// side). This holds at plain corners, convex or concave, and where the outline touches itself.
bool region_towards(const Site& point, const Vec& d, const Outline& o) {
  const auto found = o.rays.find({static_cast<int>(point.a.x()), static_cast<int>(point.a.y())});
  if (found == o.rays.end()) return false;
  double nearest = std::numeric_limits<double>::infinity();
  bool leaving = false;
  for (const Outline::Ray& r : found->second) {
    double turn = std::atan2(cross(r.direction, d), r.direction.dot(d));  // clockwise from d to r
    if (turn < 0) turn += 2.0 * std::numbers::pi;
    if (turn < nearest) nearest = turn, leaving = r.leaving;
  }
  return leaving;
}

void build_diagram(const Outline& o, Diagram& vd) {
  bp::construct_voronoi(o.segments.begin(), o.segments.end(), &vd);
}

// One finite Voronoi edge between two sites as a curve x(t), t in [0, 1] from vertex0 to vertex1. It is
// straight between two segments or two points, and a parabola between a point (its focus) and a segment
// (its directrix). Every point of it is equally far from both sites: that distance is its half-width.
class EdgeCurve {
 public:
  EdgeCurve(const Diagram::edge_type& e, const Site& s0, const Site& s1)
      : v0_(e.vertex0()->x(), e.vertex0()->y()),
        v1_(e.vertex1()->x(), e.vertex1()->y()),
        near_(s0.is_point ? s0 : s1) {
    if (s0.is_point == s1.is_point) return;
    const Site& line = s0.is_point ? s1 : s0;
    const double len = (line.b - line.a).norm();
    if (len <= 0) return;
    base_ = line.a;
    along_ = (line.b - line.a) / len;
    up_ = {-along_.y(), along_.x()};
    if ((near_.a - base_).dot(up_) < 0) up_ = -up_;
    focus_u_ = (near_.a - base_).dot(along_);
    focus_v_ = (near_.a - base_).dot(up_);
    // A focus on the directrix's line has no parabola; Boost then gives a straight edge in effect.
    parabola_ = focus_v_ > kOnOutline;
    u0_ = (v0_ - base_).dot(along_);
    u1_ = (v1_ - base_).dot(along_);
  }

  Vec at(double t) const {
    if (t <= 0) return v0_;
    if (t >= 1) return v1_;
    if (!parabola_) return v0_ + t * (v1_ - v0_);
    const double u = u0_ + t * (u1_ - u0_);
    const double v = ((u - focus_u_) * (u - focus_u_) + focus_v_ * focus_v_) / (2.0 * focus_v_);
    return base_ + u * along_ + v * up_;
  }
  // Twice the distance to the sites, exact at every point of the edge.
  double width(double t) const { return 2.0 * near_.distance(at(t)); }
  // Where the width is smallest strictly inside the edge, if it is: on either side of it the width is
  // monotone. Between two segments the width is linear and has no such point.
  std::optional<double> narrowest() const {
    double t = -1;
    if (parabola_ && u1_ != u0_) {
      t = (focus_u_ - u0_) / (u1_ - u0_);
    } else if (near_.is_point && (v1_ - v0_).squaredNorm() > 0) {
      t = (near_.a - v0_).dot(v1_ - v0_) / (v1_ - v0_).squaredNorm();
    }
    if (t > 0 && t < 1) return t;
    return std::nullopt;
  }

 private:
  Vec v0_, v1_;
  Site near_;  // the point site if there is one: the simpler distance
  bool parabola_ = false;
  Vec base_ = Vec::Zero(), along_ = Vec::Zero(), up_ = Vec::Zero();  // the directrix's frame
  double focus_u_ = 0, focus_v_ = 0, u0_ = 0, u1_ = 0;
};

// Whether a primary, finite edge lies inside the region. Edges never cross the outline (a point on a
// segment is a site's own point), so one point of the edge off the outline decides: beside a segment site
// by the side of the segment it is on, between two point sites by the side of the outline it is on at one
// of the points.
bool is_inside(const EdgeCurve& c, const Site& s0, const Site& s1, const Outline& o) {
  const Vec p = c.width(0) > c.width(1) ? c.at(0) : c.at(1);
  if (s0.is_point && s1.is_point) return region_towards(s0, p - s0.a, o);
  const Site& seg = s0.is_point ? s1 : s0;
  return cross(seg.b - seg.a, p - seg.a) > 0;
}

// The angle at x between the directions to the nearest points of two sites, or 0 if x is on one of them.
double facing_angle(const Vec& x, const Site& s0, const Site& s1) {
  const auto nearest = [&x](const Site& s) -> Vec {
    if (s.is_point) return s.a;
    const Vec d = s.b - s.a;
    return s.a + std::clamp((x - s.a).dot(d) / d.squaredNorm(), 0.0, 1.0) * d;
  };
  const Vec u = nearest(s0) - x, w = nearest(s1) - x;
  if (u.norm() < kOnOutline || w.norm() < kOnOutline) return 0.0;
  return std::atan2(std::abs(cross(u, w)), u.dot(w));
}

// Whether the outline faces itself across the edge (see kMinFacingAngleRad). The facing angle is largest
// where the edge is narrowest (180° there) and falls away from it on either side, so the ends and that
// point tell its largest value.
bool faces_across(const EdgeCurve& c, const Site& s0, const Site& s1) {
  double most = std::max(facing_angle(c.at(0), s0, s1), facing_angle(c.at(1), s0, s1));
  if (const auto t = c.narrowest()) most = std::max(most, facing_angle(c.at(*t), s0, s1));
  return most >= kMinFacingAngleRad;
}

// An edge of the diagram that is part of the medial axis, with the indices of its vertices.
struct KeptEdge {
  EdgeCurve curve;
  std::size_t vertex0, vertex1;
};

std::vector<KeptEdge> kept_edges(const Diagram& vd, const Outline& o) {
  std::vector<KeptEdge> out;
  const Diagram::vertex_type* first = vd.vertices().data();
  for (const Diagram::edge_type& e : vd.edges()) {
    if (&e > e.twin() || !e.is_primary() || !e.is_finite()) continue;  // each edge once, via its twin
    const Site s0 = site_of(*e.cell(), o);
    const Site s1 = site_of(*e.twin()->cell(), o);
    EdgeCurve c(e, s0, s1);
    if (!is_inside(c, s0, s1, o) || !faces_across(c, s0, s1)) continue;
    out.push_back(
        {c, static_cast<std::size_t>(e.vertex0() - first), static_cast<std::size_t>(e.vertex1() - first)});
  }
  return out;
}

// A point of an edge: its parameter, where it is and the width there (units).
struct Sample {
  double t = 0;
  Vec p = Vec::Zero();
  double width = 0;
};

Sample sample(const EdgeCurve& c, double t) {
  return {t, c.at(t), c.width(t)};
}

// Adds the samples strictly between a and b, splitting until both the curve and the width are within
// tolerance of the chord and of the linear interpolation.
void refine(const EdgeCurve& c, const Sample& a, const Sample& b, int depth, std::vector<Sample>& out) {
  const Sample m = sample(c, 0.5 * (a.t + b.t));
  const double tolerance = std::max(kCurveTolerance * m.width, kMinCurveTolerance);
  const double off_chord = (m.p - 0.5 * (a.p + b.p)).norm();
  const double off_width = std::abs(m.width - 0.5 * (a.width + b.width));
  if (depth >= kMaxSplits || (off_chord <= tolerance && off_width <= tolerance)) return;
  refine(c, a, m, depth + 1, out);
  out.push_back(m);
  refine(c, m, b, depth + 1, out);
}

std::vector<Sample> discretise(const EdgeCurve& c) {
  std::vector<double> breaks{0.0};
  if (const auto t = c.narrowest()) breaks.push_back(*t);
  breaks.push_back(1.0);
  std::vector<Sample> out{sample(c, 0.0)};
  for (std::size_t k = 1; k < breaks.size(); ++k) {
    const Sample b = sample(c, breaks[k]);
    refine(c, out.back(), b, 0, out);
    out.push_back(b);
  }
  return out;
}

// Where the width crosses `level` between a and b, the width being monotone between them.
double crossing(const EdgeCurve& c, double ta, double tb, double level) {
  const bool rising = c.width(tb) > c.width(ta);
  for (int k = 0; k < 60 && tb - ta > 1e-14; ++k) {
    const double tm = 0.5 * (ta + tb);
    ((c.width(tm) < level) == rising ? ta : tb) = tm;
  }
  return 0.5 * (ta + tb);
}

// The parts of a sampled edge whose width lies in [lo, hi], each as its samples in order.
std::vector<std::vector<Sample>> runs_in_range(const EdgeCurve& c, const std::vector<Sample>& samples,
                                               double lo, double hi) {
  std::vector<std::vector<Sample>> runs;
  std::vector<Sample> run;
  const auto flush = [&] {
    if (run.size() >= 2) runs.push_back(std::move(run));
    run.clear();
  };
  const auto in = [&](double w) { return w >= lo && w <= hi; };
  if (in(samples.front().width)) run.push_back(samples.front());
  for (std::size_t k = 0; k + 1 < samples.size(); ++k) {
    const Sample& a = samples[k];
    const Sample& b = samples[k + 1];
    if (in(a.width) && in(b.width)) {
      run.push_back(b);
      continue;
    }
    // The width is monotone from a to b, so the part in range is one stretch [enter, leave] or nothing.
    const bool rising = b.width >= a.width;
    const double low_end = rising ? a.width : b.width, high_end = rising ? b.width : a.width;
    if (high_end < lo || low_end > hi) {
      flush();
      continue;
    }
    const double t_lo = low_end >= lo ? (rising ? a.t : b.t) : crossing(c, a.t, b.t, lo);
    const double t_hi = high_end <= hi ? (rising ? b.t : a.t) : crossing(c, a.t, b.t, hi);
    const double enter = std::min(t_lo, t_hi), leave = std::max(t_lo, t_hi);
    if (enter > a.t) {
      flush();
      run.push_back(sample(c, enter));
    }
    if (leave > enter) run.push_back(leave < b.t ? sample(c, leave) : b);
    if (leave < b.t) flush();
  }
  flush();
  return runs;
}

// A stretch of centre line between two nodes: diagram vertices, or the cuts where the width left the range.
struct Piece {
  std::size_t from = 0, to = 0;
  std::vector<Sample> samples;
};

// Union-find over diagram vertices, joining the two ends of edges too short to be more than one vertex.
class Junctions {
 public:
  explicit Junctions(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  std::size_t find(std::size_t v) {
    while (parent_[v] != v) v = parent_[v] = parent_[parent_[v]];
    return v;
  }
  void join(std::size_t a, std::size_t b) { parent_[find(a)] = find(b); }

 private:
  std::vector<std::size_t> parent_;
};

std::vector<Piece> pieces_of(const std::vector<KeptEdge>& edges, std::size_t vertices, double lo, double hi,
                             std::size_t& nodes) {
  Junctions junctions(vertices);
  for (const KeptEdge& e : edges)
    if ((e.curve.at(1) - e.curve.at(0)).norm() < kSameVertex) junctions.join(e.vertex0, e.vertex1);
  std::vector<Piece> out;
  nodes = vertices;
  for (const KeptEdge& e : edges) {
    if ((e.curve.at(1) - e.curve.at(0)).norm() < kSameVertex) continue;
    for (std::vector<Sample>& run : runs_in_range(e.curve, discretise(e.curve), lo, hi)) {
      Piece p;
      p.from = run.front().t <= 0 ? junctions.find(e.vertex0) : nodes++;
      p.to = run.back().t >= 1 ? junctions.find(e.vertex1) : nodes++;
      p.samples = std::move(run);
      out.push_back(std::move(p));
    }
  }
  return out;
}

// Chains the pieces into lines through the nodes where exactly two meet, unless that is on the outline (two
// sharp corners meeting at a point where the outline touches itself); what is left after the open lines are
// closed loops.
std::vector<std::vector<Sample>> chain(const std::vector<Piece>& pieces, std::size_t nodes) {
  std::vector<std::vector<std::size_t>> at(nodes);
  std::vector<bool> end(nodes, false);
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const Piece& p = pieces[k];
    at[p.from].push_back(k);
    at[p.to].push_back(k);
    if (p.samples.front().width < 2 * kOnOutline) end[p.from] = true;
    if (p.samples.back().width < 2 * kOnOutline) end[p.to] = true;
  }
  for (std::size_t n = 0; n < nodes; ++n) end[n] = end[n] || at[n].size() != 2;
  std::vector<bool> used(pieces.size(), false);
  const auto walk = [&](std::size_t node, std::size_t k) {
    std::vector<Sample> line;
    while (!used[k]) {
      used[k] = true;
      const Piece& p = pieces[k];
      const bool forward = p.from == node;
      std::vector<Sample> s = p.samples;
      if (!forward) std::reverse(s.begin(), s.end());
      line.insert(line.end(), s.begin() + (line.empty() ? 0 : 1), s.end());
      node = forward ? p.to : p.from;
      if (end[node]) break;
      k = at[node][0] == k ? at[node][1] : at[node][0];
    }
    return line;
  };
  std::vector<std::vector<Sample>> lines;
  for (std::size_t n = 0; n < nodes; ++n)
    if (end[n])
      for (std::size_t k : at[n])
        if (!used[k]) lines.push_back(walk(n, k));
  for (std::size_t k = 0; k < pieces.size(); ++k)
    if (!used[k]) {
      std::vector<Sample> loop = walk(pieces[k].from, k);
      loop.back() = loop.front();  // closed: the same point to the last bit
      lines.push_back(std::move(loop));
    }
  return lines;
}

}  // namespace

std::vector<CentreLine> medial_axis(const Polygons& region, double min_width_mm, double max_width_mm) {
  if (!(min_width_mm >= 0) || !(max_width_mm >= min_width_mm))
    throw InternalError("medial_axis: width range [" + std::to_string(min_width_mm) + ", " +
                        std::to_string(max_width_mm) + "] mm is empty or not a number");
  const Frame frame = frame_for(region);
  const Outline outline = outline_of(region, frame);
  if (outline.segments.empty()) return {};
  Diagram vd;
  build_diagram(outline, vd);
  const double lo = min_width_mm * frame.scale - kWidthSlack, hi = max_width_mm * frame.scale + kWidthSlack;
  std::size_t nodes = 0;
  const std::vector<Piece> pieces = pieces_of(kept_edges(vd, outline), vd.vertices().size(), lo, hi, nodes);
  std::vector<CentreLine> out;
  for (const std::vector<Sample>& line : chain(pieces, nodes)) {
    if (line.size() < 2) continue;
    CentreLine c;
    for (const Sample& s : line) {
      c.points.push_back(frame.origin + s.p / frame.scale);
      c.width_mm.push_back(s.width / frame.scale);
    }
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace beadtwin::slicer
