// Tests of the filling of slits one voxel thin (sim/slits.hpp) on hand-made grids whose answer can be
// counted.
#include "sim/slits.hpp"

#include <gtest/gtest.h>

namespace beadtwin::sim {
namespace {

// A slab 10 x 10 x 7 voxels, full, cut through at k = 3 by a slit `thick` voxels thin (fill 0.2) across
// the whole slab, so open on all four sides; with `groove`, also a groove one voxel wide and one deep along
// y at i = 5 in the top row.
openvdb::FloatGrid::Ptr slab(int thick, bool groove) {
  openvdb::FloatGrid::Ptr fill = openvdb::FloatGrid::create(0.0f);
  auto acc = fill->getAccessor();
  for (int k = 0; k < 7; ++k)
    for (int j = 0; j < 10; ++j)
      for (int i = 0; i < 10; ++i) {
        const bool cut = (k >= 3 && k < 3 + thick) || (groove && i == 5 && k == 6);
        acc.setValue({i, j, k}, cut ? 0.2f : 1.0f);
      }
  return fill;
}

// The voxels set to 1 that were not.
int filled(const openvdb::FloatGrid& fill, const openvdb::FloatGrid& before) {
  int n = 0;
  const auto was = before.getConstAccessor();
  for (auto it = fill.cbeginValueOn(); it; ++it) n += *it == 1.0f && was.getValue(it.getCoord()) != 1.0f;
  return n;
}

// One voxel thin: its inside is filled, its mouth (the ring of slit voxels at the slab's sides) is not.
TEST(Slits, TheInsideOfASlitOneVoxelThinIsFilledButNotItsMouth) {
  const openvdb::FloatGrid::Ptr before = slab(1, false);
  const openvdb::FloatGrid::Ptr fill = before->deepCopy();
  fill_slits(*fill, 0.5);
  EXPECT_EQ(filled(*fill, *before), 8 * 8);
  EXPECT_EQ(fill->tree().getValue({0, 4, 3}), 0.2f);  // the mouth
  EXPECT_EQ(fill->tree().getValue({4, 4, 3}), 1.0f);
  EXPECT_EQ(fill->activeVoxelCount(), before->activeVoxelCount());
}

// Two voxels thin: no slit. A groove one voxel deep is its own mouth: not filled either.
TEST(Slits, ThickerSlitsAndGroovesStay) {
  const openvdb::FloatGrid::Ptr two = slab(2, false);
  openvdb::FloatGrid::Ptr fill = two->deepCopy();
  fill_slits(*fill, 0.5);
  EXPECT_EQ(filled(*fill, *two), 0);
  const openvdb::FloatGrid::Ptr grooved = slab(2, true);
  fill = grooved->deepCopy();
  fill_slits(*fill, 0.5);
  EXPECT_EQ(filled(*fill, *grooved), 0);
}

// A threshold below the slit's fill makes it solid: nothing to fill.
TEST(Slits, TheThresholdDecidesWhatIsSolid) {
  const openvdb::FloatGrid::Ptr before = slab(1, false);
  const openvdb::FloatGrid::Ptr fill = before->deepCopy();
  fill_slits(*fill, 0.1);
  EXPECT_EQ(filled(*fill, *before), 0);
}

}  // namespace
}  // namespace beadtwin::sim
