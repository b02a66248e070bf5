#include "slicer/centre_beads.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace beadtwin::slicer {
namespace {

bool is_closed(const CentreLine& l) {
  return l.points.size() > 2 && (l.points.front() - l.points.back()).norm() < 1e-9;
}

// Unit direction leaving the line at its end (`at_end`) or its start.
Eigen::Vector2d end_direction(const CentreLine& l, bool at_end) {
  const std::size_t n = l.points.size();
  const Eigen::Vector2d d = at_end ? l.points[n - 1] - l.points[n - 2] : l.points[0] - l.points[1];
  return d.norm() > 0 ? Eigen::Vector2d(d.normalized()) : Eigen::Vector2d::Zero();
}

// How many line ends (other than this one) lie at `p`: a junction of the medial axis.
bool at_junction(const std::vector<CentreLine>& lines, std::size_t self, bool at_end) {
  const Eigen::Vector2d p = at_end ? lines[self].points.back() : lines[self].points.front();
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (is_closed(lines[i])) continue;
    for (const bool e : {false, true}) {
      if (i == self && e == at_end) continue;
      const Eigen::Vector2d q = e ? lines[i].points.back() : lines[i].points.front();
      if ((p - q).norm() < 1e-6) return true;
    }
  }
  return false;
}

// Runs a free end on: half its width, then (while it has not reached `meet`) up to `reach_on` more.
void extend_end(CentreLine& l, bool at_end, const Polygons& meet, double reach_on) {
  const Eigen::Vector2d d = end_direction(l, at_end);
  if (d.isZero()) return;
  const Eigen::Vector2d p = at_end ? l.points.back() : l.points.front();
  const double w = at_end ? l.width_mm.back() : l.width_mm.front();
  double go = 0.5 * w;
  if (reach_on > 0 && !meet.empty() && !contains(meet, p + go * d)) {
    const double step = std::max(reach_on / 32.0, 1e-3);
    for (double t = step; t <= reach_on + 1e-9; t += step)
      if (contains(meet, p + (go + t) * d)) {
        go += t;
        break;
      }
  }
  if (at_end) {
    l.points.push_back(p + go * d);
    l.width_mm.push_back(w);
  } else {
    l.points.insert(l.points.begin(), p + go * d);
    l.width_mm.insert(l.width_mm.begin(), w);
  }
}

// Joins open lines whose ends are within `gap` (nearest pairs first), end to start.
void stitch(std::vector<CentreLine>& lines, double gap) {
  while (gap > 0) {
    double best = std::numeric_limits<double>::infinity();
    std::size_t bi = 0, bj = 0;
    bool bi_end = false, bj_end = false;
    for (std::size_t i = 0; i < lines.size(); ++i)
      for (std::size_t j = i + 1; j < lines.size(); ++j) {
        if (is_closed(lines[i]) || is_closed(lines[j])) continue;
        for (const bool ei : {false, true})
          for (const bool ej : {false, true}) {
            const Eigen::Vector2d p = ei ? lines[i].points.back() : lines[i].points.front();
            const Eigen::Vector2d q = ej ? lines[j].points.back() : lines[j].points.front();
            if ((p - q).norm() < best) best = (p - q).norm(), bi = i, bj = j, bi_end = ei, bj_end = ej;
          }
      }
    if (!(best <= gap)) return;
    CentreLine a = lines[bi], b = lines[bj];
    if (!bi_end)
      std::reverse(a.points.begin(), a.points.end()), std::reverse(a.width_mm.begin(), a.width_mm.end());
    if (bj_end)
      std::reverse(b.points.begin(), b.points.end()), std::reverse(b.width_mm.begin(), b.width_mm.end());
    const bool same = (a.points.back() - b.points.front()).norm() < 1e-9;
    a.points.insert(a.points.end(), b.points.begin() + (same ? 1 : 0), b.points.end());
    a.width_mm.insert(a.width_mm.end(), b.width_mm.begin() + (same ? 1 : 0), b.width_mm.end());
    lines.erase(lines.begin() + static_cast<std::ptrdiff_t>(bj));
    lines[bi] = std::move(a);
  }
}

// Splits segments along which the thickness changes by more than `step_mm` (the thickness varies linearly
// along a straight piece of the medial axis), so each bead segment can take the width of its own stretch.
void subdivide(CentreLine& l, double step_mm) {
  CentreLine out;
  for (std::size_t i = 0; i + 1 < l.points.size(); ++i) {
    const int parts =
        std::max(1, static_cast<int>(std::ceil(std::abs(l.width_mm[i + 1] - l.width_mm[i]) / step_mm)));
    for (int k = 0; k < parts; ++k) {
      const double t = static_cast<double>(k) / parts;
      out.points.push_back(l.points[i] + t * (l.points[i + 1] - l.points[i]));
      out.width_mm.push_back(l.width_mm[i] + t * (l.width_mm[i + 1] - l.width_mm[i]));
    }
  }
  out.points.push_back(l.points.back());
  out.width_mm.push_back(l.width_mm.back());
  l = std::move(out);
}

// The line as beads: constant-width runs within the deviation; one bead where one may be that wide, two
// side by side where it is wider.
std::vector<CentreBead> to_beads(const CentreLine& l, const CentreBeadRules& rules) {
  const std::size_t n = l.points.size();
  std::vector<double> seg(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) seg[i] = 0.5 * (l.width_mm[i] + l.width_mm[i + 1]);
  if (rules.thickness_deviation_mm > 0) {
    // Runs whose thickness stays within the deviation of the run's first segment take their mean width.
    for (std::size_t start = 0; start < seg.size();) {
      std::size_t end = start + 1;
      while (end < seg.size() && std::abs(seg[end] - seg[start]) <= rules.thickness_deviation_mm) ++end;
      double mean = 0;
      for (std::size_t i = start; i < end; ++i) mean += seg[i];
      mean /= static_cast<double>(end - start);
      std::fill(seg.begin() + static_cast<std::ptrdiff_t>(start),
                seg.begin() + static_cast<std::ptrdiff_t>(end), mean);
      start = end;
    }
  }
  // Runs of segments that take one bead, and runs too wide for one: those get two, each half as wide, a
  // quarter of the width either side of the centre line (one out along one side, back along the other).
  std::vector<CentreBead> out;
  for (std::size_t start = 0; start < seg.size();) {
    const bool two = seg[start] > rules.one_bead_width_mm;
    std::size_t end = start + 1;
    while (end < seg.size() && (seg[end] > rules.one_bead_width_mm) == two) ++end;
    if (!two) {
      out.push_back({{l.points.begin() + static_cast<std::ptrdiff_t>(start),
                      l.points.begin() + static_cast<std::ptrdiff_t>(end + 1)},
                     {seg.begin() + static_cast<std::ptrdiff_t>(start),
                      seg.begin() + static_cast<std::ptrdiff_t>(end)}});
    } else {
      CentreBead left, right;
      for (std::size_t i = start; i <= end; ++i) {
        const Eigen::Vector2d t =
            (l.points[std::min(i + 1, n - 1)] - l.points[i == 0 ? 0 : i - 1]).normalized();
        const Eigen::Vector2d normal(-t.y(), t.x());
        left.points.push_back(l.points[i] + 0.25 * l.width_mm[i] * normal);
        right.points.push_back(l.points[i] - 0.25 * l.width_mm[i] * normal);
      }
      for (std::size_t i = start; i < end; ++i)
        left.widths_mm.push_back(0.5 * seg[i]), right.widths_mm.push_back(0.5 * seg[i]);
      std::reverse(right.points.begin(), right.points.end());
      std::reverse(right.widths_mm.begin(), right.widths_mm.end());
      out.push_back(std::move(left));
      out.push_back(std::move(right));
    }
    start = end;
  }
  return out;
}

}  // namespace

std::vector<CentreBead> centre_beads(const Polygons& pieces, const Polygons& meet,
                                     const CentreBeadRules& rules) {
  std::vector<CentreLine> lines = medial_axis(pieces, rules.min_width_mm, rules.max_width_mm);
  lines.erase(
      std::remove_if(lines.begin(), lines.end(), [](const CentreLine& l) { return l.points.size() < 2; }),
      lines.end());
  // Which ends are free is decided on the lines as the medial axis gives them, before any end moves.
  std::vector<std::pair<bool, bool>> free(lines.size());
  for (std::size_t i = 0; i < lines.size(); ++i)
    free[i] = {!is_closed(lines[i]) && !at_junction(lines, i, false),
               !is_closed(lines[i]) && !at_junction(lines, i, true)};
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (free[i].first) extend_end(lines[i], false, meet, rules.intersection_distance_mm);
    if (free[i].second) extend_end(lines[i], true, meet, rules.intersection_distance_mm);
  }
  stitch(lines, rules.stitching_gap_mm);
  // Fine enough that a bead's width never strays more than 2 % of the width (or a quarter of the allowed
  // deviation) from the wall's thickness.
  for (CentreLine& l : lines) {
    const double widest = *std::max_element(l.width_mm.begin(), l.width_mm.end());
    subdivide(l, rules.thickness_deviation_mm > 0 ? 0.25 * rules.thickness_deviation_mm : 0.02 * widest);
  }
  std::vector<CentreBead> out;
  for (const CentreLine& l : lines)
    for (CentreBead& b : to_beads(l, rules)) out.push_back(std::move(b));
  return out;
}

int lay_centre_beads(LayerBuilder& b, const std::vector<CentreBead>& beads, Feature feature) {
  int laid = 0;
  for (const CentreBead& bead : beads) {
    if (bead.points.size() < 2) continue;
    b.travel_to(bead.points.front());
    b.event(ExtruderEvent::kMeltOn);
    for (std::size_t i = 1; i < bead.points.size(); ++i)
      b.print_thin(bead.points[i], bead.widths_mm[i - 1], feature);
    b.event(ExtruderEvent::kMeltOff);
    ++laid;
  }
  return laid;
}

}  // namespace beadtwin::slicer
