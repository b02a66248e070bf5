// Tests of the local porosity field (sim/porosity.hpp) on hand-made grids whose answer can be counted.
#include "sim/porosity.hpp"

#include <vector>

#include <gtest/gtest.h>

#include <openvdb/tools/VolumeToMesh.h>
#include <tbb/global_control.h>

namespace beadtwin::sim {
namespace {

// A solid block of 11 x 11 x 11 voxels with an empty channel one voxel wide along y through its middle
// (x = z = 5), the channel's voxels marked as enclosed gaps.
struct Channel {
  openvdb::FloatGrid::Ptr fill = openvdb::FloatGrid::create(0.0f);
  openvdb::MaskGrid::Ptr gaps = openvdb::MaskGrid::create();
  Channel() {
    fill->setTransform(openvdb::math::Transform::createLinearTransform(2.0));
    gaps->setTransform(fill->transform().copy());
    auto f = fill->getAccessor();
    auto g = gaps->getAccessor();
    for (int x = 0; x < 11; ++x)
      for (int y = 0; y < 11; ++y)
        for (int z = 0; z < 11; ++z) {
          if (x == 5 && z == 5)
            g.setValueOn({x, y, z});
          else
            f.setValue({x, y, z}, 1.0f);
        }
  }
};

// The surface in voxel faces: the block's six sides of 11 x 11 faces less the channel's two mouths, and the
// channel's four walls 11 voxels long; the block spans leaves (8 voxels a side), so faces are counted across
// their borders too. The fill's iso-surface at one half, meshed at adaptivity 0, has a quad for each.
TEST(Porosity, CountsTheSurfaceInVoxelFaces) {
  const Channel c;
  const Porosity p = measure_porosity(*c.fill, 3);
  EXPECT_EQ(p.surface_faces, 6u * 121u - 2u + 4u * 11u);
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(*c.fill, points, triangles, quads, 0.5, 0.0);
  EXPECT_EQ(quads.size() + triangles.size() / 2, p.surface_faces);
  // A voxel half full is solid; one a little less is not.
  openvdb::FloatGrid::Ptr two = openvdb::FloatGrid::create(0.0f);
  two->tree().setValue({0, 0, 0}, 0.5f);
  two->tree().setValue({1, 0, 0}, 0.49f);
  EXPECT_EQ(measure_porosity(*two, 3).surface_faces, 6u);
}

TEST(LocalPorosity, CountsTheVoidInTheCubeAroundAVoxel) {
  const Channel c;
  const openvdb::FloatGrid::Ptr p = local_porosity(*c.fill, *c.gaps, 1);
  auto at = p->getConstAccessor();
  // On the channel: 3 of the 27 voxels of the cube are empty gap.
  EXPECT_NEAR(at.getValue({5, 5, 5}), 3.0f / 27.0f, 1e-6f);
  // Beside it: the same 3 voxels of the cube.
  EXPECT_NEAR(at.getValue({4, 5, 5}), 3.0f / 27.0f, 1e-6f);
  // Two voxels away the cube holds no gap.
  EXPECT_FLOAT_EQ(at.getValue({3, 5, 5}), 0.0f);
  // At the block's corner the outside air counts in neither part: solid, 0.
  EXPECT_FLOAT_EQ(at.getValue({0, 0, 0}), 0.0f);
  // Where the channel meets the block's face (y = 0), the cube is cut by the air: 2 gap voxels of 18.
  EXPECT_NEAR(at.getValue({5, 0, 5}), 2.0f / 18.0f, 1e-6f);
  EXPECT_TRUE(p->transform() == c.fill->transform());
}

TEST(LocalPorosity, SameOnOneAndTwoThreads) {
  const Channel c;
  const auto run = [&](int threads) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return local_porosity(*c.fill, *c.gaps, 2);
  };
  const openvdb::FloatGrid::Ptr one = run(1), two = run(2);
  auto b = two->getConstAccessor();
  std::size_t count = 0;
  for (auto it = one->cbeginValueOn(); it; ++it, ++count) EXPECT_EQ(*it, b.getValue(it.getCoord()));
  EXPECT_EQ(count, 11u * 11u * 11u);
}

}  // namespace
}  // namespace beadtwin::sim
