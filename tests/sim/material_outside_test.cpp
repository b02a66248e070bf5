// Tests of the material outside the CAD (sim/material_outside.hpp): a block of voxels cut by a CAD box's top
// face, counted by hand.
#include "sim/material_outside.hpp"

#include <gtest/gtest.h>

#include "sim/cad_field.hpp"
#include "sim/deposit.hpp"
#include "slicer/mesh.hpp"
#include "tests/sim/voxel_block.hpp"

namespace beadtwin::sim {
namespace {

// A block of 10 x 10 x 10 voxels of 1 mm, against a box over the same footprint 4.5 mm tall: the voxel rows
// k = 5..9 lie wholly outside (share 1), the row k = 4 is cut through its centre (share 1/2), the rest lie
// inside (share 0, the box's side faces running along the voxels' outer faces). So 550 of the 1000 full
// voxels' material is outside. A voxel half full outside counts half.
TEST(MaterialOutside, ABlockCutByTheCadsTop) {
  const openvdb::FloatGrid::Ptr fill = testing::full_block({10, 10, 10});
  auto acc = fill->getAccessor();
  const slicer::TriangleMesh box = slicer::make_box({10, 10, 4.5});
  const openvdb::FloatGrid::Ptr distance =
      cad_distance_grid({box.vertices, box.triangles}, fill->transform(), 2.0f);
  MaterialOutside m = measure_material_outside(*fill, *distance, 1.0);
  EXPECT_NEAR(m.volume_mm3, 550.0, 1e-3);
  EXPECT_NEAR(m.fraction, 0.55, 1e-6);
  acc.setValue({3, 3, 9}, 0.5f);
  m = measure_material_outside(*fill, *distance, 1.0);
  EXPECT_NEAR(m.volume_mm3, 549.5, 1e-3);
  EXPECT_NEAR(m.fraction, 549.5 / 999.5, 1e-6);
  // Voxels of 2 mm: each voxel's material is its fill times 8 mm³.
  fill->setTransform(deposit_transform(2.0));
  const openvdb::FloatGrid::Ptr coarse =
      cad_distance_grid({box.vertices, box.triangles}, fill->transform(), 2.0f);
  EXPECT_GT(measure_material_outside(*fill, *coarse, 2.0).volume_mm3, 8 * 500.0);
  // Nothing: nothing outside.
  const MaterialOutside empty = measure_material_outside(*openvdb::FloatGrid::create(0.0f), *distance, 1.0);
  EXPECT_EQ(empty.volume_mm3, 0.0);
  EXPECT_EQ(empty.fraction, 0.0);
}

}  // namespace
}  // namespace beadtwin::sim
