#include "slicer/triangulate.hpp"

#include <cstddef>

#include <Eigen/Geometry>

namespace beadtwin::slicer {

std::vector<std::array<int, 3>> triangulate_polygon(const std::vector<Eigen::Vector3d>& corners) {
  const int n = static_cast<int>(corners.size());
  std::vector<std::array<int, 3>> out;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // Newell's normal: twice the area, along the normal
  for (int i = 0; i < n; ++i) normal += corners[i].cross(corners[(i + 1) % n]);
  std::vector<int> left(n);
  for (int i = 0; i < n; ++i) left[i] = i;
  const auto fan = [&] {
    for (std::size_t i = 1; i + 1 < left.size(); ++i) out.push_back({left[0], left[i], left[i + 1]});
  };
  constexpr int kMaxEarClipping = 256;
  if (!(normal.norm() > 0.0) || !normal.allFinite() || n > kMaxEarClipping) {
    fan();
    return out;
  }
  // The plane's 2-D coordinates, turned so that the polygon runs counter-clockwise in them.
  const Eigen::Vector3d z = normal.normalized();
  const Eigen::Vector3d x = z.unitOrthogonal();
  const Eigen::Vector3d y = z.cross(x);
  std::vector<Eigen::Vector2d> p(n);
  for (int i = 0; i < n; ++i) p[i] = {corners[i].dot(x), corners[i].dot(y)};
  const auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
    return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
  };
  while (left.size() > 3) {
    const std::size_t m = left.size();
    bool clipped = false;
    for (std::size_t i = 0; i < m && !clipped; ++i) {
      const int a = left[(i + m - 1) % m], b = left[i], c = left[(i + 1) % m];
      if (cross(p[a], p[b], p[c]) <= 0.0) continue;  // a reflex or straight corner is no ear
      bool empty = true;
      for (std::size_t j = 0; j < m && empty; ++j) {
        const int q = left[j];
        if (q == a || q == b || q == c) continue;
        empty = !(cross(p[a], p[b], p[q]) >= 0.0 && cross(p[b], p[c], p[q]) >= 0.0 &&
                  cross(p[c], p[a], p[q]) >= 0.0);
      }
      if (!empty) continue;
      out.push_back({a, b, c});
      left.erase(left.begin() + static_cast<std::ptrdiff_t>(i));
      clipped = true;
    }
    if (!clipped) break;
  }
  fan();
  return out;
}

}  // namespace beadtwin::slicer
