#include "slicer/layer_builder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <utility>

#include "core/units.hpp"

namespace beadtwin::slicer {

namespace {

// Arc length along a closed contour from vertex 0 to each vertex, and the total (at index n).
std::vector<double> arc_lengths(const Polygon& poly) {
  std::vector<double> at(poly.size() + 1, 0.0);
  for (std::size_t i = 0; i < poly.size(); ++i)
    at[i + 1] = at[i] + (poly[(i + 1) % poly.size()] - poly[i]).norm();
  return at;
}

// The point at arc length `s` (modulo the perimeter), as (segment, parameter).
std::pair<std::size_t, double> locate(const Polygon& poly, const std::vector<double>& at, double s) {
  const double total = at.back();
  s = total > 0 ? std::fmod(std::fmod(s, total) + total, total) : 0.0;
  std::size_t seg = static_cast<std::size_t>(std::upper_bound(at.begin(), at.end(), s) - at.begin());
  seg = std::min(seg == 0 ? 0 : seg - 1, poly.size() - 1);
  const double len = at[seg + 1] - at[seg];
  return {seg, len > 0 ? std::clamp((s - at[seg]) / len, 0.0, 1.0) : 0.0};
}

// Where a pass may start when it must not start in a corner: the nearest arc length at or after `s` that
// lies at least `clear_mm` from every corner (a turn of 30° or more). Contours without room anywhere start
// in the middle of their longest corner-to-corner run.
double off_corners(const Polygon& poly, const std::vector<double>& at, double s, double clear_mm) {
  const std::size_t n = poly.size();
  const double total = at.back();
  std::vector<double> corners;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d a = (poly[i] - poly[(i + n - 1) % n]).normalized();
    const Eigen::Vector2d b = (poly[(i + 1) % n] - poly[i]).normalized();
    if (a.dot(b) < std::cos(30.0 * kPi / 180.0)) corners.push_back(at[i]);
  }
  if (corners.empty() || total <= 0) return s;
  s = std::fmod(std::fmod(s, total) + total, total);
  double best_shift = std::numeric_limits<double>::infinity(), longest = -1.0, longest_mid = s;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    // The run from corner k to the next one (wrapping), and the part of it clear of both.
    const double from = corners[k];
    double to = corners[(k + 1) % corners.size()];
    if (to <= from) to += total;
    if (to - from > longest) longest = to - from, longest_mid = 0.5 * (from + to);
    const double lo = from + clear_mm, hi = to - clear_mm;
    if (lo > hi) continue;
    for (const double base : {s, s + total}) {
      const double shift =
          base < lo ? lo - base : (base <= hi ? 0.0 : std::numeric_limits<double>::infinity());
      best_shift = std::min(best_shift, shift);
    }
  }
  return std::isfinite(best_shift) ? s + best_shift : longest_mid;
}

}  // namespace

Polygon start_at(const Polygon& poly, const Eigen::Vector2d& near, double advance_mm,
                 double corner_clear_mm) {
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
  // Then `advance_mm` on along the contour (the seam offset), and off any corner.
  const std::vector<double> at = arc_lengths(poly);
  double s = at[seg] + t_best * (at[seg + 1] - at[seg]) + std::max(0.0, advance_mm);
  if (corner_clear_mm > 0) s = off_corners(poly, at, s, corner_clear_mm);
  double t = 0.0;
  std::tie(seg, t) = locate(poly, at, s);
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

Polygon blunt_corners(const Polygon& loop, double min_interior_deg, double cut_mm) {
  if (min_interior_deg <= 0 || loop.size() < 3) return loop;
  // Material lies to the left of every contour (outer contours run counter-clockwise, holes clockwise), so
  // a left turn is a corner of the material; its interior angle is 180° less the turn.
  const std::size_t n = loop.size();
  Polygon out;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d prev = loop[(i + n - 1) % n], p = loop[i], next = loop[(i + 1) % n];
    const Eigen::Vector2d a = p - prev, b = next - p;
    const double turn = turn_rad(a, b) * 180.0 / kPi;
    if (turn <= 0 || 180.0 - turn >= min_interior_deg) {
      out.push_back(p);
      continue;
    }
    // Chamfer: cut back along both edges (never past their middles).
    const double back = std::min(cut_mm, 0.5 * a.norm()), ahead = std::min(cut_mm, 0.5 * b.norm());
    out.push_back(p - back * a.normalized());
    out.push_back(p + ahead * b.normalized());
  }
  return out;
}

void LayerBuilder::pull_back_corners(std::vector<Move>& moves, std::size_t first, const PullBackParams& p) {
  // The bead's print moves as a path: arc length at each move's end, and the corners (arc lengths).
  std::vector<double> corners;
  double at = 0.0;
  const double cos_min = std::cos(p.min_turn_deg * kPi / 180.0);
  for (std::size_t i = first; i < moves.size(); ++i) {
    if (moves[i].kind != MoveKind::kPrint) continue;
    at += moves[i].length_mm();
    const std::size_t j = i + 1;
    if (j >= moves.size() || moves[j].kind != MoveKind::kPrint) continue;
    const Eigen::Vector3d a = (moves[i].end - moves[i].start).normalized();
    const Eigen::Vector3d b = (moves[j].end - moves[j].start).normalized();
    if (a.dot(b) <= cos_min + 1e-12) corners.push_back(at);
  }
  if (corners.empty()) return;
  // Roller-up intervals [corner − length, corner + extension], in arc length.
  auto lifted = [&](double s) {
    for (const double c : corners)
      if (s > c - p.length_mm - 1e-9 && s < c + p.extension_mm + 1e-9) return true;
    return false;
  };
  std::vector<Move> out(moves.begin(), moves.begin() + static_cast<std::ptrdiff_t>(first));
  at = 0.0;
  for (std::size_t i = first; i < moves.size(); ++i) {
    const Move& m = moves[i];
    const double len = m.length_mm();
    if (m.kind != MoveKind::kPrint || len <= 0) {
      out.push_back(m);
      continue;
    }
    // Cut the move at every interval end that falls inside it.
    std::vector<double> cuts{0.0, len};
    for (const double c : corners)
      for (const double e : {c - p.length_mm, c + p.extension_mm})
        if (e - at > 1e-6 && e - at < len - 1e-6) cuts.push_back(e - at);
    std::sort(cuts.begin(), cuts.end());
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      Move piece = m;
      const double t0 = cuts[k] / len, t1 = cuts[k + 1] / len;
      piece.start = m.start + t0 * (m.end - m.start);
      piece.end = m.start + t1 * (m.end - m.start);
      piece.volume_mm3 = m.volume_mm3 * (t1 - t0);
      piece.roller_down = !lifted(at + 0.5 * (cuts[k] + cuts[k + 1]));
      out.push_back(piece);
    }
    at += len;
  }
  moves = std::move(out);
}

}  // namespace beadtwin::slicer
