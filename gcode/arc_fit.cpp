#include "gcode/arc_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

namespace beadtwin::gcode {
namespace {

using Eigen::Vector2d;

double cross(const Vector2d& a, const Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Why a run is not an arc. A straight run may still bend enough once it grows, so growth goes on; a run
// that does not fit ends the growth (greedy: a longer run is not tried).
enum class Fit : std::uint8_t { kArc, kStraight, kNoFit };

// Every circle through the run's first and last point has its centre on the chord's perpendicular bisector:
// one unknown, the signed offset t along the bisector's left normal.
struct Bisector {
  Vector2d mid;
  Vector2d normal;
  double half = 0.0;  // half the chord, mm
  Vector2d centre(double t) const { return mid + t * normal; }
  double radius(double t) const { return std::hypot(half, t); }
};

// Every point within `tol` of the chord from the first to the last point: an arc would gain nothing.
bool straight(std::span<const Vector2d> run, double tol) {
  const Vector2d dir = (run.back() - run.front()).normalized();
  for (const Vector2d& p : run)
    if (std::abs(cross(dir, p - run.front())) > tol) return false;
  return true;
}

// +1 when the polyline turns only left, -1 only right, 0 when it turns both ways (an inflection) or doubles
// back. Turns whose vertex sits within a rounding allowance of its neighbours' chord count as straight.
int turning(std::span<const Vector2d> run, double tol) {
  const double allowance = 1e-3 * tol;
  bool left = false;
  bool right = false;
  for (std::size_t k = 1; k + 1 < run.size(); ++k) {
    const Vector2d a = run[k] - run[k - 1];
    const Vector2d b = run[k + 1] - run[k];
    const double span = (a + b).norm();
    if (a.squaredNorm() == 0.0 || b.squaredNorm() == 0.0 || a.dot(b) <= 0.0 || span == 0.0) return 0;
    const double deviation = cross(a, b) / span;  // signed distance of run[k] from its neighbours' chord
    left = left || deviation > allowance;
    right = right || deviation < -allowance;
  }
  return left == right ? 0 : (left ? 1 : -1);
}

// Circle through the first, middle and last point.
double three_point_offset(std::span<const Vector2d> run, const Bisector& b) {
  const Vector2d v = run[run.size() / 2] - b.mid;
  const double denom = 2.0 * v.dot(b.normal);
  if (std::abs(denom) < 1e-12) return std::numeric_limits<double>::quiet_NaN();
  return (v.squaredNorm() - b.half * b.half) / denom;
}

// Gauss-Newton on the radial errors of the interior points and all segment midpoints (the end points lie on
// every candidate circle), from the three-point circle: less sensitive to one noisy middle point.
double least_squares_offset(std::span<const Vector2d> run, const Bisector& b, double t) {
  for (int iter = 0; iter < 10; ++iter) {
    const Vector2d c = b.centre(t);
    const double r = b.radius(t);
    double num = 0.0;
    double den = 0.0;
    const auto add = [&](const Vector2d& q) {
      const Vector2d d = q - c;
      const double dist = d.norm();
      if (dist == 0.0) return;
      const double g = -d.dot(b.normal) / dist - t / r;  // d(error)/dt
      num += (dist - r) * g;
      den += g * g;
    };
    for (std::size_t k = 0; k + 1 < run.size(); ++k) {
      if (k > 0) add(run[k]);
      add(0.5 * (run[k] + run[k + 1]));
    }
    if (!(den > 0.0)) break;
    const double step = num / den;
    t -= step;
    if (std::abs(step) <= 1e-12 * (1.0 + std::abs(t))) break;
  }
  return t;
}

// Signed angle the points turn through about `c` (radians, counter-clockwise positive); NaN unless every
// step advances the same way.
double sweep(std::span<const Vector2d> run, const Vector2d& c) {
  double total = 0.0;
  int sign = 0;
  for (std::size_t k = 0; k + 1 < run.size(); ++k) {
    const Vector2d a = run[k] - c;
    const Vector2d b = run[k + 1] - c;
    const double step = std::atan2(cross(a, b), a.dot(b));
    if (std::abs(step) < 1e-12) return std::numeric_limits<double>::quiet_NaN();
    const int s = step > 0.0 ? 1 : -1;
    if (sign != 0 && s != sign) return std::numeric_limits<double>::quiet_NaN();
    sign = s;
    total += step;
  }
  return total;
}

// Largest radial distance of a point or segment midpoint from the circle. The points advance monotonically
// and no step reaches half a turn, so every midpoint lies within the arc's angle: radial distance to the
// circle is the distance to the arc.
double max_error(std::span<const Vector2d> run, const Vector2d& c, double r) {
  double worst = 0.0;
  for (std::size_t k = 0; k < run.size(); ++k) {
    worst = std::max(worst, std::abs((run[k] - c).norm() - r));
    if (k + 1 < run.size()) worst = std::max(worst, std::abs((0.5 * (run[k] + run[k + 1]) - c).norm() - r));
  }
  return worst;
}

Fit fit_run(std::span<const Vector2d> run, double tol, PathPiece& arc) {
  const Vector2d chord = run.back() - run.front();
  const double length = chord.norm();
  if (length < 1e-9) return Fit::kNoFit;  // a closed loop is never one arc
  if (straight(run, tol)) return Fit::kStraight;
  const int dir = turning(run, tol);
  if (dir == 0) return Fit::kNoFit;

  const Bisector b{0.5 * (run.front() + run.back()), Vector2d(-chord.y(), chord.x()) / length, 0.5 * length};
  const double t3 = three_point_offset(run, b);
  if (!std::isfinite(t3)) return Fit::kNoFit;
  const double candidates[] = {t3, least_squares_offset(run, b, t3)};
  const double max_radius = kMaxArcRadiusPerTolerance * tol;
  const double max_sweep = kMaxArcSweepDeg * std::numbers::pi / 180.0 + 1e-9;
  bool too_large = false;
  double best = std::numeric_limits<double>::infinity();
  for (const double t : candidates) {
    if (!std::isfinite(t)) continue;
    const double r = b.radius(t);
    if (r > max_radius) {
      too_large = true;
      continue;
    }
    const Vector2d c = b.centre(t);
    const double s = sweep(run, c);
    if (!std::isfinite(s) || (s > 0.0) != (dir > 0) || std::abs(s) > max_sweep) continue;
    const double e = max_error(run, c, r);
    if (e <= tol && e < best) {
      best = e;
      arc.kind = dir > 0 ? PieceKind::kArcCcw : PieceKind::kArcCw;
      arc.end = run.back();
      arc.centre = c;
    }
  }
  if (std::isfinite(best)) return Fit::kArc;
  return too_large ? Fit::kStraight : Fit::kNoFit;
}

}  // namespace

std::vector<PathPiece> fit_arcs(std::span<const Vector2d> points, double tolerance_mm) {
  std::vector<PathPiece> pieces;
  const std::size_t n = points.size();
  std::size_t i = 0;
  while (i + 1 < n) {
    std::optional<PathPiece> longest;
    if (tolerance_mm > 0.0) {
      for (std::size_t j = i + 3; j < n && j - i <= kMaxArcSegments; ++j) {
        PathPiece arc;
        const Fit fit = fit_run(points.subspan(i, j - i + 1), tolerance_mm, arc);
        if (fit == Fit::kNoFit) break;
        if (fit == Fit::kArc) {
          arc.last_point = j;
          longest = arc;
        }
      }
    }
    if (longest) {
      pieces.push_back(*longest);
      i = longest->last_point;
    } else {
      pieces.push_back({PieceKind::kLine, points[i + 1], Vector2d::Zero(), i + 1});
      ++i;
    }
  }
  return pieces;
}

}  // namespace beadtwin::gcode
