// Tests of the heat solve's lumper (thermal/lumper.hpp): how far below the top each born cell lies, which
// runs of settled cells become one, and when it is worth looking.
#include "thermal/lumper.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "tests/thermal/test_meshes.hpp"

namespace beadtwin::thermal {
namespace {

// `count` cells of 1000 mm³ in a row along x, each touching the next (unless `gap_after` names the one
// whose contact with its successor is left out), born one a second in order.
ThermalMesh bar(int count, int gap_after = -1) {
  ThermalMesh mesh;
  mesh.voxel_size_mm = 1.0;
  for (int x = 0; x < count; ++x) mesh.cells.push_back(cell_at({x * 10.0, 0.0, 5.0}, 1000.0, x));
  for (int x = 0; x + 1 < count; ++x)
    if (x != gap_after)
      mesh.links.push_back(
          link(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(x + 1), {100.0, 0.0, 0.0}));
  return mesh;
}

// The model of `mesh` with its first `born` cells born; their temperatures in `y` (the deposition
// temperature, with room for every cell and the energy lost).
PartModel born_model(const ThermalMesh& mesh, std::size_t born, std::vector<double>& y) {
  PartModel model(mesh, test_material(), Environment{});
  y.assign(mesh.cells.size() + 1, 0.0);
  model.birth(born, y);
  return model;
}

TEST(Lumper, DepthCountsContactsFromTheCellsWithANeighbourNotYetBorn) {
  const ThermalMesh mesh = bar(10);
  std::vector<double> y;
  const PartModel model = born_model(mesh, 8, y);
  const std::vector<std::uint8_t> depth = contacts_below_top(model, 3);
  ASSERT_EQ(depth.size(), 8u);  // the born cells
  EXPECT_EQ(depth[7], 0);       // touches cell 8, not yet born
  EXPECT_EQ(depth[6], 1);
  EXPECT_EQ(depth[4], 3);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(depth[i], kFarBelowTop) << i;
  // A cell no path from the top reaches is as far as any.
  const ThermalMesh cut = bar(10, 5);
  const PartModel cut_model = born_model(cut, 8, y);
  const std::vector<std::uint8_t> cut_depth = contacts_below_top(cut_model, 50);
  EXPECT_EQ(cut_depth[6], 1);
  EXPECT_EQ(cut_depth[5], kFarBelowTop);
}

TEST(Lumper, SettledRunsAreEvenInTemperatureTouchingAndBoundedInMass) {
  const ThermalMesh mesh = bar(10);
  std::vector<double> y;
  const PartModel model = born_model(mesh, 8, y);
  const std::vector<std::uint8_t> depth = contacts_below_top(model, 3);  // cells 0-3 far below the top
  std::vector<double> state(8, 100.0);
  std::vector<std::uint32_t> to;
  const double cell_kg = model.mass_kg(0);
  EXPECT_EQ(settled_runs(model, state, depth, 0.5, 100.0 * cell_kg, to), 7u);
  EXPECT_EQ(to, (std::vector<std::uint32_t>{0, 0, 0, 0, 1, 2, 3, 4, 5, 6}));
  // A cell more than the tolerance off the run's range starts another run.
  state[2] = state[3] = 100.6;
  EXPECT_EQ(settled_runs(model, state, depth, 0.5, 100.0 * cell_kg, to), 8u);
  EXPECT_EQ(to, (std::vector<std::uint32_t>{0, 0, 1, 1, 2, 3, 4, 5, 6, 7}));
  state[2] = state[3] = 100.4;  // within it
  EXPECT_EQ(settled_runs(model, state, depth, 0.5, 100.0 * cell_kg, to), 7u);
  // At most 2.5 cells' mass a run.
  EXPECT_EQ(settled_runs(model, state, depth, 0.5, 2.5 * cell_kg, to), 8u);
  EXPECT_EQ(to, (std::vector<std::uint32_t>{0, 0, 1, 1, 2, 3, 4, 5, 6, 7}));
  // Cells that do not touch are not one run.
  const ThermalMesh cut = bar(10, 1);
  const PartModel cut_model = born_model(cut, 8, y);
  const std::vector<std::uint8_t> cut_depth = contacts_below_top(cut_model, 3);
  EXPECT_EQ(settled_runs(cut_model, std::vector<double>(8, 100.0), cut_depth, 0.5, 100.0 * cell_kg, to), 8u);
  EXPECT_EQ(to, (std::vector<std::uint32_t>{0, 0, 1, 1, 2, 3, 4, 5, 6, 7}));
}

TEST(Lumper, LooksOnceEnoughCellsWereBornAndLumpsOnlyWhenEnoughWouldGo) {
  const ThermalMesh mesh = bar(200);
  std::vector<double> y;
  const PartModel model = born_model(mesh, 190, y);
  const std::vector<double> even(190, 100.0);
  HeatOptions options;
  options.lump_depth = 3;          // cells 0-185 settled
  options.lump_max_cells = 10.5;   // runs of 10
  options.lump_check_cells = 191;  // not yet
  EXPECT_TRUE(Lumper(options, model.mass_kg(0)).settled(model, even, 190).empty());
  options.lump_check_cells = 100;
  Lumper lumper(options, model.mass_kg(0));
  const std::vector<std::uint32_t> to = lumper.settled(model, even, 190);
  ASSERT_EQ(to.size(), 200u);
  EXPECT_EQ(to[9], 0u);
  EXPECT_EQ(to[10], 1u);
  EXPECT_EQ(to[185], 18u);  // 18 runs of 10, then one of 6
  EXPECT_EQ(to[186], 19u);
  EXPECT_EQ(to[199], 32u);
  // Not again until another lump_check_cells cells were born.
  EXPECT_TRUE(lumper.settled(model, even, 289).empty());
  EXPECT_FALSE(lumper.settled(model, even, 389).empty());
  // Cells each a kelvin off the last: no run, nothing worth a restart.
  std::vector<double> uneven(190);
  for (std::size_t i = 0; i < uneven.size(); ++i) uneven[i] = 100.0 + static_cast<double>(i % 2);
  EXPECT_TRUE(lumper.settled(model, uneven, 489).empty());
}

TEST(Lumper, ACoveredBeadsSlicesBecomeOneCellWhateverTheirTemperatures) {
  // Ten cells in a row as five beads of two slices (columns 0, 2, 4, 6, 8), eight born: cells 4-7 lie 3, 2,
  // 1 and 0 contacts below the top.
  const ThermalMesh mesh = bar(10);
  std::vector<double> y;
  const PartModel model = born_model(mesh, 8, y);
  const std::vector<std::uint8_t> depth = contacts_below_top(model, 20);
  const std::vector<double> state = {100.0, 140.0, 100.0, 180.0, 100.0, 100.0, 100.0, 100.0};
  std::vector<std::uint32_t> column = {0, 0, 2, 2, 4, 4, 6, 6, 8, 8};
  std::vector<std::uint32_t> to;
  LumpRules rules{.settled = false, .column = column, .slice_depth = 2};
  // Beads 0, 2 and 4 lie at least 2 contacts down (4 and 5: 3 and 2); bead 6 does not; bead 8 is not born.
  EXPECT_EQ(settled_runs(model, state, depth, rules, to), 7u);
  EXPECT_EQ(to, (std::vector<std::uint32_t>{0, 0, 1, 1, 2, 2, 3, 4, 5, 6}));
  // A cell of no single bead (or of another) ends a run.
  column[3] = kNoColumn;
  EXPECT_EQ(settled_runs(model, state, depth, rules, to), 8u);
  EXPECT_EQ(to, (std::vector<std::uint32_t>{0, 0, 1, 2, 3, 3, 4, 5, 6, 7}));
  // With the settled cells too (cells 0-3 more than 3 contacts down): a covered bead's run comes first;
  // where there is none (cell 1 of no bead), the settled run, within its tolerance.
  const std::vector<std::uint8_t> shallow = contacts_below_top(model, 3);
  column[1] = kNoColumn;
  column[3] = 2;
  rules.settled = true;
  rules.tolerance_k = 100.0;
  rules.max_mass_kg = 100.0 * model.mass_kg(0);
  EXPECT_EQ(settled_runs(model, state, shallow, rules, to), 6u);
  EXPECT_EQ(to, (std::vector<std::uint32_t>{0, 0, 0, 0, 1, 1, 2, 3, 4, 5}));
  rules.tolerance_k = 50.0;  // cell 3, at 180 °C, is more than 50 K off cells 0-2 (100-140 °C)
  EXPECT_EQ(settled_runs(model, state, shallow, rules, to), 7u);
  EXPECT_EQ(to, (std::vector<std::uint32_t>{0, 0, 0, 1, 2, 2, 3, 4, 5, 6}));
}

}  // namespace
}  // namespace beadtwin::thermal
