// Centre lines (the medial axis) of a layer region's thin parts, for thin-wall beads (patent (50)): a wall
// too narrow for the boundary passes gets one bead down its middle, as wide as the wall is thick there.
// Curved and tapered walls follow their true centre line, not a straight fit.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "slicer/polygons.hpp"

namespace beadtwin::slicer {

// One centre line: a polyline in mm with the wall's local thickness at each point. A closed loop (the
// middle of a ring) repeats its first point, with its width, as its last point.
struct CentreLine {
  std::vector<Eigen::Vector2d> points;  // mm
  std::vector<double> width_mm;         // twice the distance from the point to the nearest boundary, mm
};

// The centre lines of the parts of `region` whose local thickness lies in [min_width_mm, max_width_mm].
//
// `region`: closed contours in mm, outer ones counter-clockwise and holes clockwise (as slicing gives them);
// overlaps are merged (non-zero winding) and self-touching or degenerate contours are cleaned up first.
// Coordinates are snapped to 1 µm (coarser only for regions over two kilometres across).
// `min_width_mm` >= 0; `max_width_mm` >= `min_width_mm` (infinity for no upper limit).
//
// The lines are the interior medial axis, split where three or more branches meet (the lines of a
// junction all end at the same point) and cut where the thickness leaves the range. Only the stretches
// across which the outline faces itself are kept: the branches into square or blunter convex corners are
// left out, so a strip's line stops half its width short of a square end, while a corner sharper than 70°
// keeps its branch (there it is the wall narrowing to a point). Curved stretches (beside a concave corner)
// are split finely enough that the polyline stays within 0.5% of the width of the true curve; every
// point's width is exact, not interpolated.
//
// Input without area (empty, collinear, smaller than the grid) gives no lines. Throws InternalError if a
// coordinate or width is not a number, or if the width range is empty.
std::vector<CentreLine> medial_axis(const Polygons& region, double min_width_mm, double max_width_mm);

}  // namespace beadtwin::slicer
