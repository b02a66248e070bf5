// Tests of the deviation of the printed skin from the CAD (sim/skin_deviation.hpp): a skin that is a box
// 2 mm larger than the CAD's on every side, whose deviation is 2 mm on its faces and grows to 2√3 mm at its
// corners.
#include "sim/skin_deviation.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "sim/deposit.hpp"
#include "slicer/mesh.hpp"

namespace beadtwin::sim {
namespace {

constexpr double kGrown = 2.0;

struct Skin {
  std::vector<openvdb::Vec3s> points;
  std::vector<std::array<unsigned, 3>> triangles;
  explicit Skin(const slicer::TriangleMesh& mesh) {
    for (const Eigen::Vector3d& v : mesh.vertices) points.emplace_back(v.x(), v.y(), v.z());
    for (const auto& t : mesh.triangles)
      triangles.push_back(
          {static_cast<unsigned>(t[0]), static_cast<unsigned>(t[1]), static_cast<unsigned>(t[2])});
  }
};

TEST(SkinDeviation, ASkinGrownByTwoMillimetresDeviatesByTwo) {
  const slicer::TriangleMesh cad_mesh = slicer::make_box({10, 20, 30});
  const CadField cad({cad_mesh.vertices, cad_mesh.triangles}, *deposit_transform(1.0), 8.0);
  const Skin skin(
      slicer::make_box({10 + 2 * kGrown, 20 + 2 * kGrown, 30 + 2 * kGrown}, {-kGrown, -kGrown, -kGrown}));
  const NearestTriangles print(skin.points, skin.triangles);
  const SkinDeviation d = measure_skin_deviation(print, cad, 1.0, 8.0);
  const double area = 2 * (14 * 24 + 14 * 34 + 24 * 34);
  EXPECT_NEAR(d.area_mm2, area, 1e-3);
  EXPECT_GE(d.samples, static_cast<std::size_t>(area));
  EXPECT_NEAR(d.min_mm, kGrown, 1e-4);
  EXPECT_GT(d.max_mm, 1.2 * kGrown);  // off the edges and corners
  EXPECT_LT(d.max_mm, kGrown * std::sqrt(3.0));
  EXPECT_GT(d.mean_mm, kGrown);
  EXPECT_LT(d.mean_mm, kGrown * 1.1);  // mostly the faces
  EXPECT_GE(d.rms_mm, d.mean_mm);
  EXPECT_FALSE(d.min_clamped);
  EXPECT_FALSE(d.max_clamped);

  // Only the points at z >= 0: the bottom face (z = -2) and the sides' strip below 0 left out.
  const SkinDeviation above = measure_skin_deviation(print, cad, 1.0, 8.0, 0.0);
  EXPECT_NEAR(above.area_mm2, area - 14 * 24 - 2 * (14 + 24) * kGrown, 0.03 * area);
  EXPECT_LT(above.samples, d.samples);

  // The same skin as the CAD: no deviation but the grid's interpolation, exact on a flat face and a little
  // outside within a voxel of an edge, where the distance bends.
  const Skin same(cad_mesh);
  const SkinDeviation none =
      measure_skin_deviation(NearestTriangles(same.points, same.triangles), cad, 1.0, 8.0);
  EXPECT_NEAR(none.mean_mm, 0.0, 0.02);
  EXPECT_NEAR(none.rms_mm, 0.0, 0.05);
}

// With a band narrower than the corners' distance, the most is the band's edge, flagged.
TEST(SkinDeviation, BeyondTheBandIsClamped) {
  const slicer::TriangleMesh cad_mesh = slicer::make_box({10, 20, 30});
  const CadField cad({cad_mesh.vertices, cad_mesh.triangles}, *deposit_transform(1.0), 3.0);
  const Skin skin(
      slicer::make_box({10 + 2 * kGrown, 20 + 2 * kGrown, 30 + 2 * kGrown}, {-kGrown, -kGrown, -kGrown}));
  const SkinDeviation d =
      measure_skin_deviation(NearestTriangles(skin.points, skin.triangles), cad, 1.0, 3.0);
  EXPECT_TRUE(d.max_clamped);
  EXPECT_EQ(d.max_mm, 3.0);
  EXPECT_FALSE(d.min_clamped);
}

}  // namespace
}  // namespace beadtwin::sim
