// G2/G3 arcs as the straight moves of the Toolpath IR (core/toolpath.hpp): the G-code reader
// (gcode/block_reader.hpp) linearises every arc it reads within a chord tolerance.
//
// An arc turns in one of three planes, each named by two axes (u, v) and its normal n, so that u × v = n:
// G17 XY (normal Z), G18 ZX (normal Y), G19 YZ (normal X). G2 turns clockwise and G3 counter-clockwise seen
// from the normal's positive side (ISO 6983). The normal axis moves linearly with the angle turned: a helix.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace beadtwin::gcode {

enum class ArcPlane : std::uint8_t {
  kXY,  // G17
  kZX,  // G18
  kYZ,  // G19
};

// The axes (0 = X, 1 = Y, 2 = Z) of a plane: u and v span it, n is its normal.
struct PlaneAxes {
  int u = 0;
  int v = 1;
  int n = 2;
};
PlaneAxes plane_axes(ArcPlane plane);

// The centre of the arc of radius |radius_mm| from `start` to `end` (mm; the R word): the shorter arc for a
// positive radius, the longer one for a negative radius. Only the in-plane coordinates matter; the centre's
// normal coordinate is the start's. A radius short of half the chord by no more than the rounding of a
// program (0.02 mm) gives the half circle. Throws std::invalid_argument when start and end coincide in the
// plane or the radius is too short for the chord.
Eigen::Vector3d arc_centre_from_radius(const Eigen::Vector3d& start, const Eigen::Vector3d& end,
                                       ArcPlane plane, bool clockwise, double radius_mm);

// The points that replace the arc from `start` to `end` about `centre` (mm), after the start: the last is
// `end` exactly. Start and end coinciding in the plane make a full circle. `turns` >= 1 is the number of
// times the arc passes its end's angle (the P word of G2/G3: turns − 1 extra full circles). Points lie on
// the circle (on a spiral from the start's radius to the end's when a program's rounding makes them
// differ); the chords between them stay within `chord_tolerance_mm` (> 0) of it. The normal axis moves in
// proportion to the angle. Throws std::length_error when more than `max_points` points would be needed.
std::vector<Eigen::Vector3d> linearise_arc(const Eigen::Vector3d& start, const Eigen::Vector3d& end,
                                           const Eigen::Vector3d& centre, ArcPlane plane, bool clockwise,
                                           int turns, double chord_tolerance_mm, std::size_t max_points);

}  // namespace beadtwin::gcode
