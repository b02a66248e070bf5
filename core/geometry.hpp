// Small plane-geometry helpers shared by the slicer and the deposit.
#pragma once

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

namespace beadtwin {

// The angle (radians) the direction turns by from `u` to `v`: positive to the left (counter-clockwise),
// negative to the right, in (−π, π].
inline double turn_rad(const Eigen::Vector2d& u, const Eigen::Vector2d& v) {
  return std::atan2(u.x() * v.y() - u.y() * v.x(), u.dot(v));
}

// Distance from `p` to the segment a-b (to `a` when the segment has no length).
inline double distance_to_segment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                                  const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return (a + t * d - p).norm();
}

}  // namespace beadtwin
