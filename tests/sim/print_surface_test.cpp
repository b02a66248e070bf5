// Tests of the print as the comparison with the CAD measures it (sim/print_surface.hpp): the plate's row, the
// print made solid and its surface, on hand-made grids.
#include "sim/print_surface.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "sim/deposit.hpp"

namespace beadtwin::sim {
namespace {

// A block of full voxels, 1 mm, i 0..19, j 0..9, k from `k0` to 9, with a closed cavity at i 8..11, j 4..5,
// k 5..6; a faint voxel (fill 0.3) below it at k = k0 - 2.
openvdb::FloatGrid::Ptr block(int k0) {
  openvdb::FloatGrid::Ptr fill = openvdb::FloatGrid::create(0.0f);
  fill->setTransform(deposit_transform(1.0));
  auto acc = fill->getAccessor();
  for (int k = k0; k < 10; ++k)
    for (int j = 0; j < 10; ++j)
      for (int i = 0; i < 20; ++i) {
        const bool cavity = i >= 8 && i < 12 && j >= 4 && j < 6 && k >= 5 && k < 7;
        if (!cavity) acc.setValue({i, j, k}, 1.0f);
      }
  acc.setValue({5, 5, k0 - 2}, 0.3f);
  return fill;
}

TEST(PrintSurface, ThePlateIsUnderTheLowestPrintedRow) {
  EXPECT_EQ(plate_row(*block(2)), 2);  // the faint voxel below is not print
  EXPECT_EQ(plate_row(*block(-3)), -3);
  openvdb::FloatGrid::Ptr faint = openvdb::FloatGrid::create(0.0f);
  faint->tree().setValue({0, 0, 0}, 0.49f);
  EXPECT_THROW((void)plate_row(*faint), InputError);
}

// On the plate: the cavity filled and the lowest row copied down `depth` voxels; off it, the cavity filled
// and nothing added.
TEST(PrintSurface, TheSolidPrintFillsTheCavityAndStandsOnThePlate) {
  const openvdb::FloatGrid::Ptr fill = block(2);
  const openvdb::FloatGrid::Ptr on = solid_print(*fill, 2, /*on_plate=*/true, 3);
  EXPECT_EQ(on->tree().getValue({9, 4, 5}), 1.0f);
  for (int k = -1; k < 2; ++k) {
    EXPECT_EQ(on->tree().getValue({0, 0, k}), 1.0f) << k;
    EXPECT_EQ(on->tree().getValue({19, 9, k}), 1.0f) << k;
  }
  EXPECT_EQ(on->tree().getValue({0, 0, -2}), 0.0f);
  EXPECT_EQ(on->tree().getValue({20, 0, 1}), 0.0f);
  EXPECT_EQ(on->tree().getValue({5, 5, 0}), 1.0f);    // the faint voxel lay below the plate: covered
  EXPECT_EQ(fill->tree().getValue({9, 4, 5}), 0.0f);  // the deposit's own fill is left as it was
  const openvdb::FloatGrid::Ptr off = solid_print(*fill, 2, /*on_plate=*/false, 3);
  EXPECT_EQ(off->tree().getValue({9, 4, 5}), 1.0f);
  EXPECT_EQ(off->tree().getValue({0, 0, 1}), 0.0f);
  EXPECT_EQ(off->activeVoxelCount(), fill->activeVoxelCount() + 4 * 2 * 2);
}

// The surface of the solid block: the faces of its voxels, facing out; the cavity filled is no surface.
TEST(PrintSurface, TheSurfaceIsTheBlocksFacesFacingOut) {
  const openvdb::FloatGrid::Ptr solid = solid_print(*block(2), 2, false, 0);
  const NearestTriangles surface = print_surface(solid);
  EXPECT_GT(surface.triangles(), 0u);
  // Above the top face (z = 10 mm), beside a side face (x = 20 mm), and inside, nearer the top than the
  // filled cavity's walls (which would be 0.5 mm away).
  const NearestTriangles::Distance above = surface.distance({10.0, 5.0, 13.0}, 5.0);
  EXPECT_NEAR(above.mm, 3.0, 1e-4);
  EXPECT_TRUE(above.outside);
  const NearestTriangles::Distance beside = surface.distance({21.5, 5.0, 6.0}, 5.0);
  EXPECT_NEAR(beside.mm, 1.5, 1e-4);
  EXPECT_TRUE(beside.outside);
  const NearestTriangles::Distance inside = surface.distance({10.0, 5.0, 7.5}, 5.0);
  EXPECT_NEAR(inside.mm, 2.5, 1e-4);
  EXPECT_FALSE(inside.outside);
}

}  // namespace
}  // namespace beadtwin::sim
