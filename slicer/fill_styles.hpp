// Fill styles of the patent's fill passes ((56)-(65), FIGS. 15-20) as a path generator: the lines that
// cover a layer's fill region, and how the head links them (printed turns, or melt off and travel).
// Pure geometry, independent of the layer builder; coordinates in mm, angles in radians.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "slicer/polygons.hpp"

namespace beadtwin::slicer {

// How the lines are laid and linked (FIGS. 15-19).
enum class FillStyle : std::uint8_t {
  kOneWay,                      // FIG. 15: every line in the same direction, travel back after each
  kSimpleZigzag,                // FIG. 16: serpentine over the whole region, lifting over holes
  kSmartZigzag,                 // FIG. 17: serpentine per hole-free cell, never over a hole
  kSmartZigzagConstantOverlap,  // FIG. 18: smart zigzag, each cell's width divided evenly
  kSparseZigzag,                // FIG. 19: a sparse serpentine first, then serpentines filling its gaps
};

// What plan_fill lays: the style and its geometry.
struct FillPattern {
  FillStyle style = FillStyle::kSmartZigzag;
  double angle_rad = 0;              // direction of the fill lines
  double bead_width_mm = 20;         // w, > 0
  double overlap = 0.1;              // least overlap between neighbouring lines, fraction of w, in [0, 1)
  double max_overlap = 0.5;          // constant overlap: the most it may go up to, in [overlap, 1)
  double max_sparse_spacing_mm = 0;  // sparse: most centre-to-centre spacing of the first serpentine (0: 2 w)
  bool sparse_fill_gaps = true;      // sparse: then lay the passes that fill its gaps (false: stays sparse)
  double min_fill_length_mm = 0;     // lines shorter than this are left out (patent (63))
  bool link_with_rapids = false;     // every line its own path: melt off, travel, melt on between lines
  double turn_link_max_mm = 0;       // longest printed turn (0: 1.5 times the serpentine's line spacing)
  double fillet_radius_mm = 0;       // round the corners of turns (patent (64)); capped at half the spacing
  bool turns_outside = false;        // turns placed w/2 outside the region (patent (64))
  double line_extension_mm = 0;      // every line's ends run on by this (patent (65))
  double line_matching_limit_mm = 0;  // patent (64): see plan_fill (0: never extend)
};

// One straight move of the head to `to`. `corner`: part of a turn between lines (for corner flow and speed).
struct FillSegment {
  Eigen::Vector2d to;
  bool print = true;
  bool corner = false;
};

// One continuous head motion without melt off: printed lines and turns, and non-printing moves over holes
// (simple zigzag and one-way only). Between paths the layer builder melts off, travels and melts on.
struct FillPath {
  Eigen::Vector2d start;
  std::vector<FillSegment> segments;
  // Whether the path's first and last points are free bead ends (that may run on into the boundary); an
  // end pulled back against a bead laid before it (a sparse gap pass meeting a turn) is not.
  bool free_start = true;
  bool free_end = true;
};

// The fill of `region`, the area bead centres may reach (already inside the boundary passes; outer contours
// counter-clockwise, holes clockwise).
//
// Lines run along `angle_rad` at pitch w (1 - overlap), centred in the region's extent across them so the
// leftover splits evenly on both sides; the constant-overlap style instead divides each cell's width evenly
// with an overlap in [overlap, max_overlap] (beside a neighbouring cell the last gap reaches the
// neighbour's line). The sparse style lays every k-th line first, k = floor(max spacing / pitch), then
// serpentines in the gaps, one per remaining residue, each starting where the previous ended.
//
// Serpentine styles link consecutive lines with a printed turn (corner segments) when it is no longer than
// the turn limit and stays inside the region grown by max(w/2, the line's run-on); otherwise a new path
// starts. Two lines whose ends are not even (the turn would not be perpendicular) are evened, the shorter
// one extended, if they differ by no more than `line_matching_limit_mm`; beyond it they are not bridged. With
// the limit 0 they are bridged by a slanted turn if it is short enough. The smart styles serpentine each
// cell of a boustrophedon decomposition (monotone cells along the lines' normal) and move on to the cell
// whose start is nearest, so a path never crosses a hole.
//
// Throws InputError naming every parameter out of range.
std::vector<FillPath> plan_fill(const Polygons& region, const FillPattern& pattern);

}  // namespace beadtwin::slicer
