#include "render/surface.hpp"

#include <string>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "tests/render/box_deposit.hpp"

namespace beadtwin::render {
namespace {

openvdb::FloatGrid::Ptr block(float value, int n, double voxel_mm) {
  auto grid = openvdb::FloatGrid::create(0.0f);
  grid->setTransform(openvdb::math::Transform::createLinearTransform(voxel_mm));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) grid->tree().setValue(openvdb::Coord(i, j, k), value);
  return grid;
}

TEST(ExtractSurface, FullBlockGivesItsVoxelFaces) {
  // 10^3 full voxels of 2 mm, centres at 0..18 mm: faces at -1 and 19 mm, halfway to the empty neighbours.
  const SurfaceMesh mesh = extract_surface(*block(1.0f, 10, 2.0));
  ASSERT_FALSE(mesh.triangles.empty());
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(mesh.bounds.min()[a], -1.0f, 1e-4f);
    EXPECT_NEAR(mesh.bounds.max()[a], 19.0f, 1e-4f);
  }
  ASSERT_EQ(mesh.normals.size(), mesh.points.size());
  for (const auto& n : mesh.normals) EXPECT_NEAR(n.norm(), 1.0f, 1e-5f);
  // Closed surface: the triangles' vector areas cancel.
  Eigen::Vector3d area = Eigen::Vector3d::Zero();
  double total = 0.0;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d n =
        (mesh.points[t[1]] - mesh.points[t[0]]).cross(mesh.points[t[2]] - mesh.points[t[0]]).cast<double>();
    area += n;
    total += n.norm();
  }
  // A cube of side 20 mm, less the one-voxel chamfer the isosurface of a 0/1 field puts on its edges.
  EXPECT_LT(0.5 * total, 6 * 20.0 * 20.0);
  EXPECT_GT(0.5 * total, 0.9 * 6 * 20.0 * 20.0);
  EXPECT_LT(area.norm(), 1e-3 * total);
}

TEST(ExtractSurface, NothingDepositedThrows) {
  const auto empty = openvdb::FloatGrid::create(0.0f);
  EXPECT_THROW(extract_surface(*empty), InputError);
  try {
    extract_surface(*block(0.3f, 4, 1.0));
    FAIL() << "a surface from voxels less than half full";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nothing was deposited"), std::string::npos) << e.what();
  }
}

TEST(LayerProbe, FindsTheLayerUnderTheSurface) {
  testing::BoxPart part;  // centreline square [0, 200]^2, 21 mm beads, 5 mm layers
  const sim::Deposit deposit = testing::make_box_deposit(part);
  LayerProbe probe(*deposit.layer);
  const Eigen::Vector3f inward = Eigen::Vector3f::UnitY();
  // The outer face of the y = 0 wall is at y = -10.5 mm; mid-height of layer k is at 5k + 2.5 mm.
  for (const int k : {0, 3, 11}) {
    const Eigen::Vector3f point(100.0f, -10.5f, 5.0f * static_cast<float>(k) + 2.5f);
    EXPECT_EQ(probe.layer_at(point, inward), k) << "layer " << k;
  }
  // Just outside the surface: the half-voxel step lands in the air, the neighbourhood finds the wall.
  EXPECT_EQ(probe.layer_at(Eigen::Vector3f(100.0f, -12.6f, 27.5f), inward), 5);
  // Far from any material.
  EXPECT_EQ(probe.layer_at(Eigen::Vector3f(100.0f, 100.0f, 27.5f), inward), -1);
}

}  // namespace
}  // namespace beadtwin::render
