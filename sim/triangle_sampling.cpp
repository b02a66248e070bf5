#include "sim/triangle_sampling.hpp"

namespace beadtwin::sim {

TriangleGrid::TriangleGrid(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                           double spacing_mm) {
  using Vec3 = Eigen::Vector3d;
  const double ab = (b - a).squaredNorm(), bc = (c - b).squaredNorm(), ca = (a - c).squaredNorm();
  const auto [p, q, r] = ab >= bc && ab >= ca ? std::array<const Vec3*, 3>{&a, &b, &c}
                         : bc >= ca           ? std::array<const Vec3*, 3>{&b, &c, &a}
                                              : std::array<const Vec3*, 3>{&c, &a, &b};
  origin = *p;
  spacing = spacing_mm;
  length = (*q - *p).norm();
  x_axis = length > 0 ? Vec3((*q - *p) / length) : Vec3::UnitX();
  const Vec3 to_apex = *r - *p;
  apex_x = to_apex.dot(x_axis);
  const Vec3 up = to_apex - apex_x * x_axis;
  height = up.norm();
  y_axis = height > 0 ? Vec3(up / height) : Vec3::Zero();
  rows = std::max(1.0, std::ceil(height / spacing_mm));
}

std::size_t count_samples(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                          double spacing_mm, std::size_t limit) {
  const TriangleGrid grid(a, b, c, spacing_mm);
  if (grid.rows > static_cast<double>(limit)) return limit + 1;
  double total = 0.0;
  for (double j = 0; j < grid.rows; ++j) {
    total += grid.columns(j);
    if (total > static_cast<double>(limit)) return limit + 1;
  }
  return static_cast<std::size_t>(total);
}

}  // namespace beadtwin::sim
