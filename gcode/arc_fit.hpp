// Arc fitting for print programs: a run of short straight print moves is written back as circular arcs
// (G2/G3) wherever an arc stays within the arc chord tolerance of the moves. Thermwood patent paragraph
// (45): "The arc chord tolerance parameter is a distance controlling the fit of the arcs of the applicator
// head to the toolpath ... decreasing the value of the arc chord tolerance may produce arcs over the
// toolpath having a smoother shape."
//
// The Toolpath IR stays straight moves (core/toolpath.hpp); only program writers fit arcs, at the edge.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace beadtwin::gcode {

enum class PieceKind : std::uint8_t {
  kLine,   // straight to `end`
  kArcCw,  // clockwise arc (G2 seen from +Z) to `end` about `centre`
  kArcCcw  // counter-clockwise arc (G3)
};

// One piece of a fitted path, from the end of the piece before it (or the first input point) to `end`.
struct PathPiece {
  PieceKind kind = PieceKind::kLine;
  Eigen::Vector2d end = Eigen::Vector2d::Zero();     // mm; always one of the input points, unchanged
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // mm; arcs only
  std::size_t last_point = 0;                        // index of `end` in the input points
  bool is_arc() const { return kind != PieceKind::kLine; }
};

// Limits on the arcs fit_arcs accepts, beyond the tolerance.
inline constexpr std::size_t kMaxArcSegments = 256;         // segments one arc may replace (bounds work)
inline constexpr double kMaxArcSweepDeg = 180.0;            // a full circle becomes at least two arcs
inline constexpr double kMaxArcRadiusPerTolerance = 1.0e5;  // radius bound, as a multiple of the tolerance

// Replaces runs of a polyline by arcs where they fit; everything else stays one line per segment.
//
// `points` are the polyline's vertices in order, mm (the start of the first move, then each move's end).
// `tolerance_mm` is the arc chord tolerance; <= 0 (or fewer than 4 points) gives one line per segment.
//
// An arc replaces points i..j only if it replaces at least 3 segments; every point i..j and every segment
// midpoint lies within `tolerance_mm` of the arc (radial distance); the polyline turns one way only and its
// points advance monotonically around the centre in that direction; the arc sweeps at most kMaxArcSweepDeg;
// and the run is not straight (its points are not all within `tolerance_mm` of the chord from i to j, and
// the radius is at most kMaxArcRadiusPerTolerance * tolerance_mm). Arcs start and end exactly on input
// points, so the pieces chain like the original moves. Arcs are grown greedily from the first point, each
// as long as it keeps fitting.
//
// Returns the pieces in order; the last one ends on the last point (empty for fewer than 2 points).
std::vector<PathPiece> fit_arcs(std::span<const Eigen::Vector2d> points, double tolerance_mm);

}  // namespace beadtwin::gcode
