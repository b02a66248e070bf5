// Tests of the heat solve's interface index (thermal/interface_index.hpp): the interfaces listed from the
// mesh's links, by the mesh cell that opens them and by model cell, before and after cells are lumped.
#include "thermal/interface_index.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "tests/thermal/test_meshes.hpp"

namespace beadtwin::thermal {
namespace {

// Four cells in a row along x on a layer, each with a cell laid on it: cells 0-3 below, 4-7 above. The links
// along a row are inside a bead; those between the rows are interfaces facing up, and one between cells 3
// and 4 (the end of the lower row and the start of the upper one) faces along x.
ThermalMesh two_rows() {
  ThermalMesh mesh;
  mesh.voxel_size_mm = 1.0;
  for (int z = 0; z < 2; ++z)
    for (int x = 0; x < 4; ++x)
      mesh.cells.push_back(cell_at({x * 10.0, 0.0, z * 4.0}, 400.0, z * 10.0 + x, z));
  for (std::uint32_t x = 0; x + 1 < 4; ++x) {
    mesh.links.push_back(link(x, x + 1, {40.0, 0.0, 0.0}));
    mesh.links.push_back(link(x + 4, x + 5, {40.0, 0.0, 0.0}));
  }
  for (std::uint32_t x = 0; x < 4; ++x) mesh.links.push_back(link(x, x + 4, {0.0, 0.0, 100.0}, true));
  mesh.links.push_back(link(3, 4, {40.0, 0.0, 1.0}, true));
  return mesh;
}

// A model cell's entries as (interface, other cell, younger cell).
using Entry = std::array<std::uint32_t, 3>;
std::vector<Entry> entries(std::span<const InterfaceIndex::CellInterface> list) {
  std::vector<Entry> out;
  for (const InterfaceIndex::CellInterface& c : list) out.push_back({c.interface, c.other, c.younger});
  return out;
}

TEST(InterfaceIndex, ListsTheInterfaceLinksInOrderWithTheirAreaAndWhetherTheYoungerLandsOnTop) {
  const std::vector<InterfaceResult> interfaces = list_interfaces(two_rows());
  ASSERT_EQ(interfaces.size(), 5u);
  for (std::uint32_t x = 0; x < 4; ++x) {
    EXPECT_EQ(interfaces[x].older, x);
    EXPECT_EQ(interfaces[x].younger, x + 4);
    EXPECT_DOUBLE_EQ(interfaces[x].area_mm2, 100.0);
    EXPECT_TRUE(interfaces[x].on_top);
  }
  EXPECT_EQ(interfaces[4].older, 3u);
  EXPECT_EQ(interfaces[4].younger, 4u);
  EXPECT_FALSE(interfaces[4].on_top);  // 1 mm² up for 40 along x: a side contact
}

TEST(InterfaceIndex, IndexesByYoungerMeshCellAndByModelCell) {
  const std::vector<InterfaceResult> interfaces = list_interfaces(two_rows());
  const InterfaceIndex index(interfaces, 8);
  EXPECT_EQ(index.size(), 5u);
  EXPECT_EQ(index.model_cells(), 8u);
  EXPECT_TRUE(index.of_younger(0).empty());
  ASSERT_EQ(index.of_younger(4).size(), 2u);  // landed on cell 0, and beside cell 3
  EXPECT_EQ(index.of_younger(4)[0], 0u);
  EXPECT_EQ(index.of_younger(4)[1], 4u);
  ASSERT_EQ(index.of_younger(7).size(), 1u);
  EXPECT_EQ(index.of_younger(7)[0], 3u);
  // Cell 3 meets cells 7 (interface 3) and 4 (interface 4), each time as the older; cell 4 meets 0 and 3.
  EXPECT_EQ(entries(index.of_cell(3)), (std::vector<Entry>{{3, 7, 7}, {4, 4, 4}}));
  EXPECT_EQ(entries(index.of_cell(4)), (std::vector<Entry>{{0, 0, 4}, {4, 3, 4}}));
  for (std::size_t g = 0; g < 8; ++g) EXPECT_FALSE(index.has_inner(g)) << g;
  EXPECT_EQ(index.cells(2)[0], 2u);
  EXPECT_EQ(index.cells(2)[1], 6u);
}

TEST(InterfaceIndex, AnInterfaceInsideALumpedCellIsInner) {
  const std::vector<InterfaceResult> interfaces = list_interfaces(two_rows());
  InterfaceIndex index(interfaces, 8);
  // Cells 2, 3 and 4 lumped into model cell 2: model cells 0, 1, 2 (2-4), 3 (5), 4 (6), 5 (7).
  const std::vector<std::uint32_t> model_of = {0, 1, 2, 2, 2, 3, 4, 5, 6};
  index.index(model_of);
  EXPECT_EQ(index.model_cells(), 6u);
  ASSERT_TRUE(index.has_inner(2));
  ASSERT_EQ(index.inner(2).size(), 1u);
  EXPECT_EQ(index.inner(2)[0], 4u);  // cells 3 and 4 are both in it
  EXPECT_EQ(index.cells(3)[0], 2u);  // interface 3: cell 3 (now 2) under cell 7 (now 5)
  EXPECT_EQ(index.cells(3)[1], 5u);
  // Model cell 2 meets cell 0 (interface 0, from mesh cell 4) and model cells 4 and 5 above (interfaces 2
  // and 3, from mesh cells 2 and 3).
  EXPECT_EQ(entries(index.of_cell(2)), (std::vector<Entry>{{0, 0, 2}, {2, 4, 4}, {3, 5, 5}}));
  EXPECT_EQ(index.of_younger(4).size(), 2u);  // by mesh cell: unchanged
}

}  // namespace
}  // namespace beadtwin::thermal
