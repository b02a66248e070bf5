// Tests of the area-weighted sampling of a triangle (sim/triangle_sampling.hpp).
#include "sim/triangle_sampling.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

namespace beadtwin::sim {
namespace {

using Vec3 = Eigen::Vector3d;

std::vector<SampleCell> cells_of(const Vec3& a, const Vec3& b, const Vec3& c, double spacing) {
  std::vector<SampleCell> cells;
  for_each_cell(a, b, c, spacing, [&](const SampleCell& cell) { cells.push_back(cell); });
  return cells;
}

// Whether p lies in triangle (a, b, c) (within a rounding), by its barycentric coordinates in the plane.
bool inside(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double area = n.squaredNorm();
  const double u = (c - b).cross(p - b).dot(n) / area, v = (a - c).cross(p - c).dot(n) / area;
  const double w = 1.0 - u - v, eps = 1e-9;
  return u >= -eps && v >= -eps && w >= -eps && std::abs((p - a).dot(n.normalized())) < 1e-9;
}

// A triangle askew in space, 30 mm on its longest side: its cells tile it, each sample lies in its cell's
// part of the triangle, and each cell's radius reaches its farthest corner.
TEST(TriangleSampling, CellsTileTheTriangle) {
  const Vec3 a(1.0, 2.0, 3.0), b(25.0, 8.0, -4.0), c(9.0, 19.0, 7.0);
  const double spacing = 2.0;
  const std::vector<SampleCell> cells = cells_of(a, b, c, spacing);
  const double area = 0.5 * (b - a).cross(c - a).norm();
  double sum = 0.0;
  for (const SampleCell& cell : cells) {
    sum += cell.area;
    EXPECT_TRUE(inside(cell.point, a, b, c)) << cell.point.transpose();
    EXPECT_GE(cell.corners, 3u);
    EXPECT_LE(cell.area, spacing * spacing * (1 + 1e-12));
    for (std::size_t k = 0; k < cell.corners; ++k) {
      EXPECT_TRUE(inside(cell.corner[k], a, b, c));
      EXPECT_LE((cell.corner[k] - cell.point).norm(), cell.radius + 1e-12);
    }
    EXPECT_LE(cell.radius, std::sqrt(2.0) * spacing);
  }
  EXPECT_NEAR(sum, area, 1e-9 * area);
  EXPECT_EQ(count_samples(a, b, c, spacing, 1'000'000), cells.size());
  EXPECT_GT(cells.size(), static_cast<std::size_t>(area / (spacing * spacing)));
}

// A triangle that fits one cell is one sample at its centroid, holding its whole area.
TEST(TriangleSampling, ASmallTriangleIsOneSampleAtItsCentroid) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0.2, 0.7, 0.1);
  const std::vector<SampleCell> cells = cells_of(a, b, c, 2.0);
  ASSERT_EQ(cells.size(), 1u);
  EXPECT_LT((cells[0].point - (a + b + c) / 3.0).norm(), 1e-15);
  EXPECT_NEAR(cells[0].area, 0.5 * (b - a).cross(c - a).norm(), 1e-15);
  EXPECT_EQ(cells[0].corners, 3u);
}

// A sliver 100 mm long and 0.1 mm wide takes one row of samples, one per spacing of its length, not the
// square of that; the walk goes back and forth, so each sample lies within two spacings of the one before.
TEST(TriangleSampling, ASliverTakesOneRowOfSamples) {
  const Vec3 a(0, 0, 0), b(100, 0, 0), c(40, 0.1, 0);
  const std::vector<SampleCell> sliver = cells_of(a, b, c, 1.0);
  EXPECT_EQ(sliver.size(), 100u);
  EXPECT_EQ(count_samples(a, b, c, 1.0, 1000), 100u);
  const Vec3 p(0, 0, 0), q(20, 0, 0), r(0, 20, 0);
  const std::vector<SampleCell> square = cells_of(p, q, r, 1.0);
  for (std::size_t i = 1; i < square.size(); ++i)
    EXPECT_LT((square[i].point - square[i - 1].point).norm(), 2.0 * std::sqrt(2.0)) << i;
  double sum = 0.0;
  for (const SampleCell& cell : square) sum += cell.area;
  EXPECT_NEAR(sum, 200.0, 1e-9);
}

// Counting stops past the limit: limit + 1.
TEST(TriangleSampling, CountingStopsPastTheLimit) {
  const Vec3 a(0, 0, 0), b(100, 0, 0), c(0, 100, 0);
  const std::size_t all = count_samples(a, b, c, 1.0, 1'000'000);
  EXPECT_GT(all, 5000u);
  EXPECT_EQ(count_samples(a, b, c, 1.0, 10), 11u);
  EXPECT_EQ(count_samples(a, b, c, 1.0, all), all);
  EXPECT_EQ(count_samples(a, b, c, 1.0, all - 1), all);
}

// sample_points gives each cell's sample and area, in the same order.
TEST(TriangleSampling, SamplePointsFollowTheCells) {
  const Vec3 a(0, 0, 0), b(7, 1, 0), c(2, 6, 3);
  const std::vector<SampleCell> cells = cells_of(a, b, c, 1.5);
  std::size_t i = 0;
  sample_points(a, b, c, 1.5, [&](const Vec3& p, double area) {
    ASSERT_LT(i, cells.size());
    EXPECT_EQ(p, cells[i].point);
    EXPECT_EQ(area, cells[i].area);
    ++i;
  });
  EXPECT_EQ(i, cells.size());
}

}  // namespace
}  // namespace beadtwin::sim
