#include "render/surface.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

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

// The quads are cut along their shorter diagonal and laid out as Embree cuts a quad, and a hit on a quad at
// Embree's quad coordinates is the same point on the triangle primitive_hit names (Embree's manual,
// RTC_GEOMETRY_TYPE_QUAD: the triangles v0, v1, v3 and v2, v3, v1, the second's coordinates taken as 1 - u,
// 1 - v). A sphere-like blob, so that the quads are bent and their diagonals differ.
TEST(ExtractSurface, QuadsAreTracedAsEmbreeCutsThem) {
  auto grid = openvdb::FloatGrid::create(0.0f);
  grid->setTransform(openvdb::math::Transform::createLinearTransform(1.0));
  for (int i = -8; i <= 8; ++i)
    for (int j = -8; j <= 8; ++j)
      for (int k = -8; k <= 8; ++k) {
        const float r = std::sqrt(static_cast<float>(i * i + 2 * j * j + 3 * k * k));
        if (r < 9.0f) grid->tree().setValue(openvdb::Coord(i, j, k), std::clamp(7.5f - r, 0.0f, 1.0f));
      }
  const SurfaceMesh mesh = extract_surface(*grid);
  ASSERT_GT(mesh.quads, 100u);
  const std::size_t lone = mesh.triangles.size() - 2 * mesh.quads;
  const auto at = [&](std::uint32_t t, float u, float v) {
    const auto& c = mesh.triangles[t];
    return Eigen::Vector3f((1.0f - u - v) * mesh.points[c[0]] + u * mesh.points[c[1]] +
                           v * mesh.points[c[2]]);
  };
  int cut_across = 0;  // quads whose diagonals differ in length
  for (std::uint32_t k = 0; k < mesh.quads; ++k) {
    const auto& first = mesh.triangles[lone + 2 * k];
    const auto& second = mesh.triangles[lone + 2 * k + 1];
    // a, b, d and c, d, b.
    ASSERT_EQ(second[1], first[2]);
    ASSERT_EQ(second[2], first[1]);
    const Eigen::Vector3f &a = mesh.points[first[0]], &b = mesh.points[first[1]], &c = mesh.points[second[0]],
                          &d = mesh.points[first[2]];
    EXPECT_LE((b - d).squaredNorm(), (a - c).squaredNorm() * (1.0f + 1e-6f));
    if ((b - d).squaredNorm() < 0.99f * (a - c).squaredNorm()) ++cut_across;
    for (const auto& [u, v] : {std::pair{0.2f, 0.3f}, std::pair{0.9f, 0.6f}, std::pair{0.0f, 1.0f}}) {
      // Embree's point for (u, v) on the quad a, b, c, d.
      const Eigen::Vector3f embree = u + v <= 1.0f
                                         ? Eigen::Vector3f(a + u * (b - a) + v * (d - a))
                                         : Eigen::Vector3f(c + (1.0f - u) * (d - c) + (1.0f - v) * (b - c));
      const TriangleHit on = primitive_hit(mesh, static_cast<std::uint32_t>(lone) + k, u, v);
      EXPECT_EQ(on.triangle, lone + 2 * k + (u + v <= 1.0f ? 0 : 1));
      EXPECT_LT((at(on.triangle, on.u, on.v) - embree).norm(), 1e-4f);
    }
  }
  EXPECT_GT(cut_across, 10);  // both ways of cutting are exercised
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
