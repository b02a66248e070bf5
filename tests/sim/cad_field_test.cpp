// Tests of the CAD's signed distance (sim/cad_field.hpp) against distances to a box worked out by hand.
#include "sim/cad_field.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "sim/cad_compare.hpp"
#include "slicer/mesh.hpp"

namespace beadtwin::sim {
namespace {

// The CAD's signed distance (CadField) against the distance to a box worked out by hand: the Euclidean
// distance to the nearest point of the box, negative inside. Near a face (within a voxel) it is the grid's,
// trilinear between exact values at the voxel centres, which is exact for a flat face; further out it is
// exact everywhere, also off an edge or a corner, where the distance bends and interpolating between voxel
// centres would not be (by up to a few tenths of a millimetre here). Beyond the band it reads ±band. The
// triangles' winding does not matter: the same box wound inside out gives the same distances.
TEST(CadField, TheCadsDistanceIsExactBeyondAVoxelOfItsSurface) {
  constexpr double kSize[3] = {30.0, 20.0, 10.0};
  constexpr double kVoxelMm = 2.0, kBandMm = 12.0;
  const slicer::TriangleMesh box = slicer::make_box({kSize[0], kSize[1], kSize[2]});
  std::vector<std::array<int, 3>> inside_out = box.triangles;
  for (std::array<int, 3>& t : inside_out) std::swap(t[1], t[2]);
  const auto truth = [&](const Eigen::Vector3d& p) {
    Eigen::Vector3d out;  // how far outside each pair of faces
    double inside = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
      out[a] = std::max({0.0, -p[a], p[a] - kSize[a]});
      inside = std::min({inside, p[a], kSize[a] - p[a]});
    }
    return out.norm() > 0 ? out.norm() : -inside;
  };
  CadCompareOptions o;
  o.band_mm = kBandMm;
  const Eigen::Vector3d centre(0.5 * kSize[0], 0.5 * kSize[1], 0.5 * kSize[2]);
  using Triangles = std::vector<std::array<int, 3>>;
  for (const Triangles* triangles : {&box.triangles, static_cast<const Triangles*>(&inside_out)}) {
    const CadDistance d = cad_distance({box.vertices, *triangles}, kVoxelMm, o);
    ASSERT_TRUE(d.field);
    const CadField& field = *d.field;
    // Off an edge and a corner, and over the middle of faces, outside and in, from 1.1 voxels to the band.
    const std::vector<Eigen::Vector3d> beyond = {{-3.1, -4.3, 5.0},
                                                 {kSize[0] + 2.5, 10.0, kSize[2] + 3.7},
                                                 {-2.9, -3.3, -2.7},
                                                 {kSize[0] + 5.3, -6.1, 7.9},
                                                 {15.0, 10.0, kSize[2] + 9.7},
                                                 {15.0, -2.3, 5.0},
                                                 {15.0, 10.0, 5.0},
                                                 {4.4, 10.0, 5.0},
                                                 {15.0, 3.1, 2.6}};
    for (const Eigen::Vector3d& p : beyond) {
      ASSERT_GT(std::abs(truth(p)), 1.1 * kVoxelMm);
      ASSERT_LT(std::abs(truth(p)), kBandMm);
      EXPECT_NEAR(field.at(p), truth(p), 1e-3) << p.transpose();
    }
    // Within a voxel of a face, away from its edges: the plane's distance, linear, so interpolated exactly.
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(15.0, -0.7, 5.0), Eigen::Vector3d(15.0, 0.9, 5.0),
                                     Eigen::Vector3d(12.3, 10.1, 10.6)})
      EXPECT_NEAR(field.at(p), truth(p), 1e-3) << p.transpose();
    // Beyond the band, either side of the surface.
    EXPECT_EQ(field.at({-kBandMm - 5.0, 10.0, 5.0}), kBandMm);
    EXPECT_EQ(field.at({15.0, 10.0, kSize[2] + kBandMm + 0.5}), kBandMm);
    EXPECT_LT(field.at(centre), 0.0);
    EXPECT_NEAR(field.at(centre), truth(centre), 1e-3);  // 5 mm in, inside the band
  }
  // The grid holds the exact distance at every voxel centre of its band, also in an inside corner, where the
  // distance folds: an open box's cavity, along the edge between its floor and a wall. (OpenVDB's
  // renormalization, for meshes that overlap themselves, would move these.)
  constexpr double kWall = 6.0, kFloor = 6.0;
  const slicer::TriangleMesh open =
      slicer::make_open_box({kSize[0] + 2 * kWall, kSize[1] + 2 * kWall, 30.0}, kWall, kFloor);
  const CadDistance d = cad_distance({open.vertices, open.triangles}, kVoxelMm, o);
  const openvdb::FloatGrid& grid = d.field->grid();
  int checked = 0;
  for (auto it = grid.cbeginValueOn(); it; ++it) {
    const openvdb::Vec3d w = grid.transform().indexToWorld(it.getCoord());
    const Eigen::Vector3d p(w.x() - kWall, w.y() - kWall, w.z() - kFloor);  // from the cavity's corner
    // In the cavity, nearer the floor and the wall at x = 0 than anything else.
    if (!(p.x() > 0 && p.y() > 4.0 && p.y() < kSize[1] - 4.0 && p.z() > 0 && p.x() < 4.0 && p.z() < 4.0))
      continue;
    EXPECT_NEAR(*it, std::min(p.x(), p.z()), 1e-4) << p.transpose();
    ++checked;
  }
  EXPECT_GT(checked, 10);
}

}  // namespace
}  // namespace beadtwin::sim
