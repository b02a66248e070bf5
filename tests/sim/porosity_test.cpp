// Tests of the local porosity field (sim/porosity.hpp) on hand-made grids whose answer can be counted.
#include "sim/porosity.hpp"

#include <gtest/gtest.h>

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
