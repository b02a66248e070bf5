// Tests of the part's ODE system (thermal/part_model.hpp) alone: births and lumping.
#include "thermal/part_model.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <utility>
#include <vector>

#include "tests/thermal/test_meshes.hpp"

namespace beadtwin::thermal {
namespace {

// Four cells in a row along x (10 mm apart, 100 mm² contacts), open to the air on their sides.
ThermalMesh row() {
  ThermalMesh mesh;
  mesh.voxel_size_mm = 1.0;
  for (int x = 0; x < 4; ++x) {
    ThermalCell c = cell_at({x * 10.0, 0.0, 5.0}, 1000.0, x);
    c.open_area_mm2 = 400.0;
    mesh.cells.push_back(c);
  }
  for (std::uint32_t x = 0; x + 1 < 4; ++x) mesh.links.push_back(link(x, x + 1, {100.0, 0.0, 0.0}));
  return mesh;
}

TEST(PartModel, ABirthBringsInTheCellsEnthalpyAndClosesTheFacesBetweenBornCells) {
  const Material material = test_material();
  PartModel model(row(), material, Environment{});
  std::vector<double> y(5, 0.0);
  model.birth(2, y);
  EXPECT_EQ(model.born(), 2u);
  EXPECT_EQ(y[0], material.deposition_temp_c);
  EXPECT_EQ(y[2], 0.0);  // not born
  const double cell_J = model.mass_kg(0) * material.enthalpy_J_kg(Environment{}.ambient_c, 200.0);
  EXPECT_DOUBLE_EQ(model.energy_in_J(), 2.0 * cell_J);
  EXPECT_DOUBLE_EQ(model.energy_stored_J(y), 2.0 * cell_J);
  EXPECT_FALSE(model.on_top(0));
  EXPECT_TRUE(model.on_top(1));  // cell 2 is not born yet
  // At the deposition temperature, in still air: the open cell 0 cools, heat flows from nowhere else.
  double loss = 0.0;
  EXPECT_LT(model.rate(0, y.data(), loss), 0.0);
  EXPECT_GT(loss, 0.0);
}

TEST(PartModel, LumpingKeepsTheEnergyAndSumsTheContactsWithTheRest) {
  const Material material = test_material();
  PartModel model(row(), material, Environment{});
  std::vector<double> y(5, 0.0);
  model.birth(3, y);
  model.set_capacity(4);
  y = {150.0, 170.0, 190.0, 200.0, 12.5};  // the born cells' temperatures, room for one, the energy lost
  const double stored = model.energy_stored_J(y);
  const double tau_3 = model.time_constant_s(3);
  // Cells 0 and 1 become one.
  const std::vector<std::uint32_t> to = {0, 0, 1, 2};
  model.lump(to, y);
  EXPECT_EQ(model.size_of_model(), 3u);
  EXPECT_EQ(model.born(), 2u);
  EXPECT_EQ(model.capacity(), 3u);
  ASSERT_EQ(y.size(), 4u);
  EXPECT_NEAR(y[0], 160.0, 0.5);  // the temperature that holds both cells' enthalpy
  EXPECT_EQ(y[1], 190.0);
  EXPECT_EQ(y[3], 12.5);  // the energy lost carried over
  EXPECT_NEAR(model.energy_stored_J(y), stored, 1e-9 * stored);
  EXPECT_DOUBLE_EQ(model.mass_kg(0), 2.0 * model.mass_kg(1));
  ASSERT_EQ(model.neighbours(0).size(), 1u);  // the contact between its members is gone
  EXPECT_EQ(model.neighbours(0)[0], 1u);
  EXPECT_EQ(model.time_constant_s(2), tau_3);  // the last cell is as it was
}

// A stack up the z axis of 10 × 10 mm cells, 100 mm² contacts: a 5 mm bead at the bottom, one 5 mm high
// from z = 5 mm (as one cell, or as two 2.5 mm slices), and a 5 mm bead on top.
ThermalMesh stack(bool sliced) {
  ThermalMesh mesh;
  mesh.voxel_size_mm = 0.5;
  std::vector<std::pair<double, double>> cells = {{0.0, 5.0}, {5.0, 10.0}, {10.0, 15.0}};  // bottom, top
  if (sliced) cells = {{0.0, 5.0}, {5.0, 7.5}, {7.5, 10.0}, {10.0, 15.0}};
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const auto [bottom, top] = cells[i];
    mesh.cells.push_back(cell_at({0.0, 0.0, 0.5 * (bottom + top)}, 100.0 * (top - bottom)));
    if (i == 0) continue;
    ThermalLink l = link(static_cast<std::uint32_t>(i - 1), static_cast<std::uint32_t>(i), {0.0, 0.0, 100.0});
    l.face_centroid_mm = {0.0, 0.0, bottom};
    mesh.links.push_back(l);
  }
  return mesh;
}

TEST(PartModel, ABeadLumpedFromItsSlicesConductsFromItsOwnCentroid) {
  const Material material = test_material();
  std::vector<double> y(5, 0.0), y_one(4, 0.0);
  PartModel sliced(stack(true), material, Environment{}), one(stack(false), material, Environment{});
  sliced.birth(4, y);
  one.birth(3, y_one);
  // The two slices together, as the birth interval takes them, and once lumped: as the bead of one cell.
  const std::vector<std::uint32_t> slices = {1, 2};
  EXPECT_NEAR(sliced.time_constant_s(slices), one.time_constant_s(1), 1e-6 * one.time_constant_s(1));
  // Without recentring, the lump keeps its slices' short paths to the beads below and above: the bead on
  // top, with no other contact, then exchanges heat faster than with a bead of one cell under it.
  PartModel kept = sliced;
  std::vector<double> y_kept = y;
  const std::vector<std::uint32_t> to = {0, 1, 1, 2};
  kept.lump(to, y_kept);
  EXPECT_LT(kept.time_constant_s(2), 0.9 * one.time_constant_s(2));
  const std::vector<std::uint8_t> recentre = {0, 1, 0};
  sliced.lump(to, y, recentre);
  ASSERT_EQ(sliced.size_of_model(), 3u);
  for (std::size_t i = 0; i < 3; ++i)
    EXPECT_NEAR(sliced.time_constant_s(i), one.time_constant_s(i), 1e-6 * one.time_constant_s(i)) << i;
}

}  // namespace
}  // namespace beadtwin::thermal
