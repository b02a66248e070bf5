// Tests of the nearest-triangle distance (sim/nearest_triangles.hpp) against distances worked out by hand.
#include "sim/nearest_triangles.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "slicer/mesh.hpp"

namespace beadtwin::sim {
namespace {

using Vec3 = Eigen::Vector3d;

// The closest point against a brute-force search over a fine grid of the triangle's points: never further,
// and never nearer than the grid's spacing allows; at a corner's region it names the corner.
TEST(ClosestOnTriangle, IsTheNearestPointOfTheTriangle) {
  const Vec3 a(0, 0, 0), b(10, 1, 0), c(3, 8, 2);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-8.0, 18.0);
  constexpr int kSteps = 400;
  for (int trial = 0; trial < 50; ++trial) {
    const Vec3 p(coordinate(random), coordinate(random), coordinate(random) - 5.0);
    const ClosestPoint closest = closest_on_triangle(p, a, b, c);
    double brute = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= kSteps; ++i)
      for (int j = 0; i + j <= kSteps; ++j) {
        const double u = double(i) / kSteps, v = double(j) / kSteps;
        brute = std::min(brute, (a + u * (b - a) + v * (c - a) - p).norm());
      }
    const double d = (closest.point - p).norm();
    EXPECT_LE(d, brute + 1e-12) << p.transpose();
    EXPECT_GT(d, brute - 0.05) << p.transpose();  // the grid's points lie within 0.03 mm of any point
  }
  EXPECT_EQ(closest_on_triangle({-1, -1, 0}, a, b, c).corner, 0);
  EXPECT_EQ(closest_on_triangle({12, 0, 0}, a, b, c).corner, 1);
  EXPECT_EQ(closest_on_triangle({3, 10, 3}, a, b, c).corner, 2);
  const ClosestPoint edge = closest_on_triangle({5, -3, 0}, a, b, c);
  EXPECT_EQ(edge.corner, -1);
  EXPECT_NEAR((edge.point - a).cross(b - a).norm(), 0.0, 1e-9);  // on the edge ab
  const ClosestPoint face = closest_on_triangle({4, 3, 10}, a, b, c);
  EXPECT_EQ(face.corner, -1);
  EXPECT_NEAR((face.point - a).dot((b - a).cross(c - a)), 0.0, 1e-9);  // in the face's plane
}

// A box 10 x 20 x 30 mm, its triangles facing out.
struct Box {
  std::vector<openvdb::Vec3s> points;
  std::vector<std::array<unsigned, 3>> triangles;
  explicit Box(bool inside_out = false) {
    const slicer::TriangleMesh mesh = slicer::make_box({10, 20, 30});
    for (const Vec3& v : mesh.vertices) points.emplace_back(v.x(), v.y(), v.z());
    double volume = 0.0;  // six times the signed volume: positive when the triangles face out
    for (const auto& t : mesh.triangles) {
      const Vec3 &p = mesh.vertices[t[0]], &q = mesh.vertices[t[1]], &r = mesh.vertices[t[2]];
      volume += p.dot(q.cross(r));
    }
    const bool flip = (volume < 0) != inside_out;
    for (const auto& t : mesh.triangles)
      triangles.push_back({static_cast<unsigned>(t[0]), static_cast<unsigned>(flip ? t[2] : t[1]),
                           static_cast<unsigned>(flip ? t[1] : t[2])});
  }
};

double box_distance(const Vec3& p) {
  const Vec3 size(10, 20, 30);
  Vec3 out;
  double inside = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    out[a] = std::max({0.0, -p[a], p[a] - size[a]});
    inside = std::min({inside, p[a], size[a] - p[a]});
  }
  return out.norm() > 0 ? out.norm() : -inside;  // negative inside
}

// The distance to a box's triangles, and the side, off its faces, edges and corners (where the nearest
// point is shared by two or three faces and the pseudonormal tells the side), inside and out.
TEST(NearestTriangles, DistanceAndSideAgainstABox) {
  const Box box;
  const NearestTriangles surface(box.points, box.triangles);
  EXPECT_EQ(surface.triangles(), 12u);
  const std::vector<Vec3> points = {{-2.0, 10.0, 15.0}, {5.0, 10.0, 33.5},  {12.0, 23.0, 15.0},
                                    {-1.0, -1.0, -1.0}, {11.0, 21.0, 32.0}, {1.0, 10.0, 15.0},
                                    {5.0, 2.5, 28.0},   {9.9, 19.9, 0.2},   {5.0, 10.0, 15.0}};
  for (const Vec3& p : points) {
    const double truth = box_distance(p);
    const NearestTriangles::Distance d = surface.distance(p, 8.0);
    ASSERT_TRUE(d.found) << p.transpose();
    EXPECT_NEAR(d.mm, std::abs(truth), 1e-5) << p.transpose();
    EXPECT_EQ(d.outside, truth > 0) << p.transpose();
  }
  // Nothing within the radius: not found, the radius.
  const NearestTriangles::Distance far = surface.distance({-20.0, 10.0, 15.0}, 5.0);
  EXPECT_FALSE(far.found);
  EXPECT_DOUBLE_EQ(far.mm, 5.0);
  // The triangles turned inside out: the same distances, the sides swapped.
  const Box turned(true);
  const NearestTriangles inverted(turned.points, turned.triangles);
  EXPECT_TRUE(inverted.distance({-2.0, 10.0, 15.0}, 8.0).found);
  EXPECT_FALSE(inverted.distance({-2.0, 10.0, 15.0}, 8.0).outside);
  EXPECT_TRUE(inverted.distance({-1.0, -1.0, -1.0}, 8.0).found);
  EXPECT_FALSE(inverted.distance({-1.0, -1.0, -1.0}, 8.0).outside);
  EXPECT_TRUE(inverted.distance({1.0, 10.0, 15.0}, 8.0).outside);
}

}  // namespace
}  // namespace beadtwin::sim
