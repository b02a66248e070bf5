// Planar polygons for slicing and path planning. Coordinates in mm. Outer contours run counter-clockwise
// and holes clockwise, as the slicer produces them; offsetting and clipping go through Clipper.
#pragma once

#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "core/geometry.hpp"

namespace beadtwin::slicer {

using Polygon = std::vector<Eigen::Vector2d>;  // closed: the last point connects to the first
using Polygons = std::vector<Polygon>;
using Polyline = std::vector<Eigen::Vector2d>;  // open

// Signed area sum (holes count negative), mm².
double area_mm2(const Polygons& polygons);
// Total length of all contours, mm.
double perimeter_mm(const Polygons& polygons);
// Offsets all contours by `delta_mm` (negative shrinks the region). Corners stay sharp (mitred up to twice
// the offset distance, squared off beyond), so passes offset from a hole meet passes offset from the outline
// at the corners instead of leaving a rounded void between them.
Polygons offset(const Polygons& polygons, double delta_mm);
// Offsets with round joins: every point of the result's boundary lies `delta_mm` from the original (within
// `arc_tolerance_mm` on the arcs), the true constant-distance envelope.
Polygons offset_round(const Polygons& polygons, double delta_mm, double arc_tolerance_mm);
// The area beads of width `width_mm` sweep along `paths` as the deposit lays them: round outside their
// corners, square-cut at free ends; a path that ends where it starts is a closed loop without ends.
Polygons sweep(const std::vector<Polyline>& paths, double width_mm);
// Cleans up a soup of possibly overlapping or inconsistently oriented loops into a proper region
// (non-zero winding of each loop taken in its own orientation, then union).
Polygons union_nonzero(const Polygons& loops);
// Each contour simplified so it stays within `tolerance_mm` of the original (Ramer-Douglas-Peucker); the
// chord tolerance of patent (41). Contours that collapse to fewer than three points are dropped.
// With `smooth_curves` (patent (47) maintain smooth curves) curves stay curves: where the simplified contour
// would turn by more than kSmoothTurnDeg at a point the original passes smoothly, original points are put
// back until it does not.
inline constexpr double kSmoothTurnDeg = 10.0;
Polygons simplify(const Polygons& polygons, double tolerance_mm, bool smooth_curves = false);
// The contours whose own area (holes included, by absolute value) is at least `min_area_mm2`.
Polygons drop_small(const Polygons& polygons, double min_area_mm2);
// The part of `a` outside `b`.
Polygons difference(const Polygons& a, const Polygons& b);
// The part of `a` inside `b`.
Polygons intersection(const Polygons& a, const Polygons& b);
// Everything inside `a` or `b`.
Polygons unite(const Polygons& a, const Polygons& b);
// Outer contours (counter-clockwise) and holes (clockwise) of a region, each as its own list.
void split_contours(const Polygons& region, Polygons& outers, Polygons& holes);
// Parts of `lines` inside `region` (or, with `inside` false, outside it).
std::vector<Polyline> clip_lines(const std::vector<Polyline>& lines, const Polygons& region,
                                 bool inside = true);
// Point-in-region test (holes excluded).
bool contains(const Polygons& region, const Eigen::Vector2d& p);

}  // namespace beadtwin::slicer
