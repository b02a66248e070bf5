#include "slicer/layer_builder.hpp"

#include <cmath>
#include <limits>

namespace beadtwin::slicer {

Polygon start_at(const Polygon& poly, const Eigen::Vector2d& near, double advance_mm) {
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
  // Walk `advance_mm` along the contour (modulo its length).
  const double perimeter = perimeter_mm({poly});
  double left = perimeter > 0 ? std::fmod(std::max(0.0, advance_mm), perimeter) : 0.0;
  double t = t_best;
  for (std::size_t guard = 0; guard <= n; ++guard) {
    const double len = (poly[(seg + 1) % n] - poly[seg]).norm();
    const double room = (1.0 - t) * len;
    if (left <= room || len == 0.0) {
      if (len > 0) t += left / len;
      break;
    }
    left -= room;
    seg = (seg + 1) % n;
    t = 0.0;
  }
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

}  // namespace beadtwin::slicer
