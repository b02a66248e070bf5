#include "gcode/arc.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "core/units.hpp"

namespace beadtwin::gcode {
namespace {

Eigen::Vector2d in_plane(const Eigen::Vector3d& p, const PlaneAxes& a) {
  return {p[a.u], p[a.v]};
}

// Angle turned from `from` to `to`, in (0, 2π], counter-clockwise or clockwise.
double sweep(double from, double to, bool clockwise) {
  double d = std::fmod(clockwise ? from - to : to - from, 2.0 * kPi);
  if (d <= 0.0) d += 2.0 * kPi;
  return d;
}

}  // namespace

PlaneAxes plane_axes(ArcPlane plane) {
  switch (plane) {
    case ArcPlane::kXY:
      return {0, 1, 2};
    case ArcPlane::kZX:
      return {2, 0, 1};
    case ArcPlane::kYZ:
      return {1, 2, 0};
  }
  return {};
}

Eigen::Vector3d arc_centre_from_radius(const Eigen::Vector3d& start, const Eigen::Vector3d& end,
                                       ArcPlane plane, bool clockwise, double radius_mm) {
  // A program's R is rounded as its coordinates are: a half circle may come out a little short.
  constexpr double kRoundingMm = 0.02;
  const PlaneAxes a = plane_axes(plane);
  const Eigen::Vector2d s = in_plane(start, a);
  const Eigen::Vector2d chord = in_plane(end, a) - s;
  const double d = chord.norm();
  if (!(d > 1e-9))
    throw std::invalid_argument("an arc given by its radius R needs an end apart from its start");
  const double r = std::abs(radius_mm);
  const double half = d / 2.0;
  if (r < half - kRoundingMm)
    throw std::invalid_argument(
        fmt::format("radius R {:.4g} mm is too short for an arc ending {:.4g} mm from its start", r, d));
  const double h = r > half ? std::sqrt(r * r - half * half) : 0.0;
  // The centre of the shorter arc lies left of the chord for a counter-clockwise arc, right for a clockwise
  // one; the longer arc's on the other side.
  const Eigen::Vector2d left(-chord.y() / d, chord.x() / d);
  const double side = (clockwise ? -1.0 : 1.0) * (radius_mm > 0.0 ? 1.0 : -1.0);
  const Eigen::Vector2d c = s + 0.5 * chord + side * h * left;
  Eigen::Vector3d centre = start;
  centre[a.u] = c.x();
  centre[a.v] = c.y();
  return centre;
}

std::vector<Eigen::Vector3d> linearise_arc(const Eigen::Vector3d& start, const Eigen::Vector3d& end,
                                           const Eigen::Vector3d& centre, ArcPlane plane, bool clockwise,
                                           int turns, double chord_tolerance_mm, std::size_t max_points) {
  if (!(chord_tolerance_mm > 0.0)) throw std::invalid_argument("the chord tolerance must be positive");
  const PlaneAxes a = plane_axes(plane);
  const Eigen::Vector2d c = in_plane(centre, a);
  const Eigen::Vector2d s = in_plane(start, a) - c;
  const Eigen::Vector2d e = in_plane(end, a) - c;
  const double r0 = s.norm();
  const double r1 = e.norm();
  const double r = std::max(r0, r1);
  if (!(r > 1e-9)) return {end};
  const double a0 = std::atan2(s.y(), s.x());
  const bool closed = (e - s).norm() <= 1e-9 * std::max(1.0, r);
  double turned = closed ? 2.0 * kPi : sweep(a0, std::atan2(e.y(), e.x()), clockwise);
  turned += 2.0 * kPi * std::max(0, turns - 1);
  // A chord of angle φ sags r (1 − cos φ/2) from the circle; a quarter turn at most keeps the shape.
  const double max_step =
      chord_tolerance_mm < r ? std::min(kPi / 2.0, 2.0 * std::acos(1.0 - chord_tolerance_mm / r)) : kPi / 2.0;
  const double steps = std::max(1.0, std::ceil(turned / max_step - 1e-9));
  if (steps > static_cast<double>(max_points))
    throw std::length_error(fmt::format(
        "an arc of radius {:.4g} mm turning {:.4g} degrees needs {:.0f} moves at a chord tolerance of "
        "{:.4g} mm, more than the {} allowed",
        r, turned * 180.0 / kPi, steps, chord_tolerance_mm, max_points));
  const auto n = static_cast<std::size_t>(steps);
  const double dir = clockwise ? -1.0 : 1.0;
  std::vector<Eigen::Vector3d> points;
  points.reserve(n);
  for (std::size_t k = 1; k < n; ++k) {
    const double t = static_cast<double>(k) / static_cast<double>(n);
    const double angle = a0 + dir * turned * t;
    const double radius = r0 + (r1 - r0) * t;
    Eigen::Vector3d p;
    p[a.u] = c.x() + radius * std::cos(angle);
    p[a.v] = c.y() + radius * std::sin(angle);
    p[a.n] = start[a.n] + (end[a.n] - start[a.n]) * t;
    points.push_back(p);
  }
  points.push_back(end);
  return points;
}

}  // namespace beadtwin::gcode
