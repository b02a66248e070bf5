// Tests of the filling of closed voids (sim/closed_voids.hpp) on hand-made grids whose answer can be
// counted.
#include "sim/closed_voids.hpp"

#include <gtest/gtest.h>

namespace beadtwin::sim {
namespace {

bool in(int v, int from, int to) {
  return v >= from && v < to;
}

// A block of 100 x 12 x 12 solid voxels (rows of two 64-bit words) with a cavity 12 x 4 x 3 inside it, at
// x 58 to 70 (across the words' boundary); with a chimney 2 voxels across from the cavity to the top, or
// with the cavity reaching down through the block's bottom.
enum class Cavity { kClosed, kChimney, kOpenBelow };
openvdb::FloatGrid::Ptr block(Cavity cavity) {
  openvdb::FloatGrid::Ptr fill = openvdb::FloatGrid::create(0.0f);
  auto acc = fill->getAccessor();
  for (int k = 0; k < 12; ++k)
    for (int j = 0; j < 12; ++j)
      for (int i = 0; i < 100; ++i) {
        const bool hollow = (in(i, 58, 70) && in(j, 4, 8) && in(k, 4, 7)) ||
                            (cavity == Cavity::kChimney && in(i, 62, 64) && in(j, 5, 7) && k >= 7) ||
                            (cavity == Cavity::kOpenBelow && in(i, 58, 70) && in(j, 4, 8) && k < 4);
        acc.setValue({i, j, k}, hollow ? 0.1f : 1.0f);  // the cavity's voxels part full, active
      }
  return fill;
}

openvdb::CoordBBox padded(const openvdb::FloatGrid& fill) {
  openvdb::CoordBBox box = fill.evalActiveVoxelBoundingBox();
  box.expand(1);
  return box;
}

// The voxels at 1 in the cavity, and whether every voxel outside it kept its value.
int filled_in_cavity(const openvdb::FloatGrid& fill, const openvdb::FloatGrid& before) {
  int filled = 0;
  const auto was = before.getConstAccessor();
  for (auto it = fill.cbeginValueOn(); it; ++it) {
    if (*it == was.getValue(it.getCoord())) continue;
    EXPECT_EQ(*it, 1.0f);
    const openvdb::Coord c = it.getCoord();
    EXPECT_TRUE(in(c.x(), 58, 70) && in(c.y(), 4, 8) && in(c.z(), 4, 7)) << c;
    ++filled;
  }
  return filled;
}

TEST(ClosedVoids, AClosedCavityIsFilledAnOpenOneIsNot) {
  for (const Cavity cavity : {Cavity::kClosed, Cavity::kChimney}) {
    const openvdb::FloatGrid::Ptr before = block(cavity);
    const openvdb::FloatGrid::Ptr fill = before->deepCopy();
    fill_closed_voids(*fill, padded(*fill), /*open_bottom=*/true, 0.5);
    EXPECT_EQ(filled_in_cavity(*fill, *before), cavity == Cavity::kClosed ? 12 * 4 * 3 : 0);
    // Nothing outside the block is touched: the box's open sides are outside.
    EXPECT_EQ(fill->activeVoxelCount(), before->activeVoxelCount());
  }
}

// A cavity open only through the bottom: closed by the plate when the bottom is closed (the box's bottom row
// is the block's lowest), reached from below when it is open.
TEST(ClosedVoids, TheBottomIsOpenOnlyWhenAskedFor) {
  const openvdb::FloatGrid::Ptr before = block(Cavity::kOpenBelow);
  openvdb::FloatGrid::Ptr fill = before->deepCopy();
  fill_closed_voids(*fill, padded(*fill), /*open_bottom=*/true, 0.5);
  EXPECT_EQ(filled_in_cavity(*fill, *before), 0);
  fill = before->deepCopy();
  openvdb::CoordBBox on_plate = padded(*fill);
  on_plate.min().z() = 0;
  fill_closed_voids(*fill, on_plate, /*open_bottom=*/false, 0.5);
  // Every cavity voxel, below and in the cavity proper, is filled.
  int filled = 0;
  for (auto it = fill->cbeginValueOn(); it; ++it) filled += *it == 1.0f;
  EXPECT_EQ(filled, 100 * 12 * 12);
}

// The threshold decides what is solid: walls of 0.4 are no walls at 0.5, but are at 0.3.
TEST(ClosedVoids, TheThresholdDecidesWhatIsSolid) {
  openvdb::FloatGrid::Ptr fill = openvdb::FloatGrid::create(0.0f);
  auto acc = fill->getAccessor();
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 5; ++i) {
        const bool centre = i == 2 && j == 2 && k == 2;
        if (!centre) acc.setValue({i, j, k}, 0.4f);
      }
  openvdb::FloatGrid::Ptr loose = fill->deepCopy();
  fill_closed_voids(*loose, padded(*loose), true, 0.5);
  EXPECT_EQ(loose->tree().getValue({2, 2, 2}), 0.0f);
  fill_closed_voids(*fill, padded(*fill), true, 0.3);
  EXPECT_EQ(fill->tree().getValue({2, 2, 2}), 1.0f);
  EXPECT_EQ(fill->tree().getValue({0, 0, 0}), 0.4f);
}

}  // namespace
}  // namespace beadtwin::sim
