// Tests of the sky view factors (thermal/view_factor.hpp) against analytic configuration factors, and of
// the radiation the part model takes from them (thermal/part_model.hpp).
#include "thermal/view_factor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include "tests/thermal/test_meshes.hpp"
#include "thermal/part_model.hpp"

namespace beadtwin::thermal {
namespace {

// A mesh of 1 mm voxels, one cell each, on a table at z = 0: the voxels (i, j, k) of [0, nx) × [0, ny) ×
// [0, nz) for which `solid` holds, each cell in toolpath layer k and born in that order.
ThermalMesh voxel_mesh(int nx, int ny, int nz, const std::function<bool(int, int, int)>& solid) {
  ThermalMesh mesh;
  mesh.voxel_size_mm = 1.0;
  mesh.table_z_mm = 0.0;
  mesh.cell_grid = openvdb::Int32Grid::create(-1);
  auto acc = mesh.cell_grid->getAccessor();
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        if (!solid(i, j, k)) continue;
        acc.setValue(openvdb::Coord(i, j, k), static_cast<std::int32_t>(mesh.cells.size()));
        mesh.cells.push_back(cell_at({i + 0.5, j + 0.5, k + 0.5}, 1.0, static_cast<double>(k), k));
      }
  return mesh;
}

// The configuration factor between two equal coaxial parallel rectangles a × b a distance c apart
// (J. R. Howell, A Catalog of Radiation Heat Transfer Configuration Factors, 3rd ed., case C-11).
double parallel_rectangles(double a, double b, double c) {
  const double x = a / c, y = b / c, x1 = std::sqrt(1 + x * x), y1 = std::sqrt(1 + y * y);
  return 2.0 / (std::numbers::pi * x * y) *
         (std::log(x1 * y1 / std::sqrt(1 + x * x + y * y)) + x * y1 * std::atan(x / y1) +
          y * x1 * std::atan(y / x1) - x * std::atan(x) - y * std::atan(y));
}

// An open box on the table: a floor one voxel thick, walls one voxel thick around an inner side `side` and
// `height` high above the floor.
ThermalMesh open_box(int side, int height) {
  const int n = side + 2;
  return voxel_mesh(n, n, height + 1, [n](int i, int j, int k) {
    return k == 0 || i == 0 || j == 0 || i == n - 1 || j == n - 1;
  });
}

// The mean of the views of the cells in layer `layer` inside the box's walls (its floor).
CellView floor_view(const ThermalMesh& mesh, const std::vector<ViewChange>& changes, int side) {
  double sky = 0.0, table = 0.0;
  int count = 0;
  for (const ViewChange& v : changes) {
    const Eigen::Vector3d c = mesh.cells[v.cell].centroid_mm;
    if (c.z() > 1.0 || c.x() < 1.0 || c.y() < 1.0 || c.x() > side + 1.0 || c.y() > side + 1.0) continue;
    sky += v.view.sky;
    table += v.view.table;
    ++count;
  }
  EXPECT_EQ(count, side * side);
  return {.sky = static_cast<float>(sky / count), .table = static_cast<float>(table / count)};
}

TEST(ViewFactor, TheFloorOfAnOpenCubicBoxSeesTheSkyThroughItsOpening) {
  constexpr int kSide = 20;
  const ThermalMesh box = open_box(kSide, kSide);
  SkyView view(box);
  const CellView floor = floor_view(box, view.update(box.cells.size()), kSide);
  const double analytic = parallel_rectangles(1.0, 1.0, 1.0);
  EXPECT_NEAR(analytic, 0.1998, 5e-4);
  EXPECT_NEAR(floor.sky, analytic, 0.05 * analytic);
  EXPECT_EQ(floor.table, 0.0f);  // the walls hide the table
}

TEST(ViewFactor, AFlatPlateSeesTheSkyOverItsTopAndTheTableFromItsEdges) {
  // A plate 20 × 20 × 2 voxels: its inner cells' top faces see all the sky; the side faces of its edge
  // cells in the lower row see half sky, half table (an infinite plane at their foot).
  const ThermalMesh plate = voxel_mesh(20, 20, 2, [](int, int, int) { return true; });
  SkyView view(plate);
  double side_sky = 0.0, side_table = 0.0;
  int sides = 0;
  for (const ViewChange& v : view.update(plate.cells.size())) {
    const Eigen::Vector3d c = plate.cells[v.cell].centroid_mm;
    const bool edge = c.x() < 1.0 || c.x() > 19.0 || c.y() < 1.0 || c.y() > 19.0;
    if (!edge) {
      ASSERT_GT(c.z(), 1.0);  // only the top row has faces to the air away from the edges
      EXPECT_EQ(v.view.sky, 1.0f);
      EXPECT_EQ(v.view.table, 0.0f);
    } else if (c.z() < 1.0 && (c.x() < 1.0) != (c.y() < 1.0) && c.x() < 19.0 && c.y() < 19.0) {
      side_sky += v.view.sky;  // one side face each, no corner
      side_table += v.view.table;
      ++sides;
    }
  }
  ASSERT_EQ(sides, 2 * 18);
  EXPECT_NEAR(side_sky / sides, 0.5, 0.02);
  EXPECT_NEAR(side_table / sides, 0.5, 0.02);
}

TEST(ViewFactor, TheFloorOfALongChannelMatchesHottelsCrossedStrings) {
  // A channel 10 wide between walls 10 high, 160 long: away from its ends, its floor sees the sky through
  // the opening as between two infinitely long strips, F = (sqrt(H² + W²) − H) / W (crossed strings).
  constexpr int kWidth = 10, kHeight = 10, kLength = 160;
  const ThermalMesh channel = voxel_mesh(kLength, kWidth + 2, kHeight + 1, [](int, int j, int k) {
    return k == 0 || j == 0 || j == kWidth + 1;
  });
  SkyView view(channel);
  double sky = 0.0;
  int count = 0;
  for (const ViewChange& v : view.update(channel.cells.size())) {
    const Eigen::Vector3d c = channel.cells[v.cell].centroid_mm;
    if (c.z() > 1.0 || c.y() < 1.0 || c.y() > kWidth + 1.0 || std::abs(c.x() - kLength / 2.0) > 20.0)
      continue;
    sky += v.view.sky;
    ++count;
  }
  ASSERT_EQ(count, 40 * kWidth);
  const double analytic = (std::hypot(kHeight, kWidth) - kHeight) / kWidth;
  EXPECT_NEAR(sky / count, analytic, 0.05 * analytic);
}

TEST(ViewFactor, AFloorsViewShrinksAsTheWallsRiseAndIsFoundAgainWhenTheyHaveGrown) {
  // The box's layers born one at a time: the floor's view is found when its layer is complete and again
  // each time the top's height above it has grown by a quarter, each time the analytic one at that height.
  constexpr int kSide = 20;
  const ThermalMesh box = open_box(kSide, kSide);
  SkyView view(box);
  std::size_t born = 0;
  int floor_updates = 0;
  double last_sky = 2.0;
  for (int layer = 0; layer <= kSide; ++layer) {
    while (born < box.cells.size() && box.cells[born].layer <= layer) ++born;
    const std::vector<ViewChange> changes = view.update(born);
    int floor_cells = 0;
    for (const ViewChange& v : changes) floor_cells += box.cells[v.cell].layer == 0 ? 1 : 0;
    if (floor_cells == 0) continue;
    ++floor_updates;
    const CellView floor = floor_view(box, changes, kSide);
    // The walls stand `layer` voxels above the floor's top face.
    const double analytic = layer == 0 ? 1.0 : parallel_rectangles(kSide, kSide, layer);
    EXPECT_NEAR(floor.sky, analytic, 0.05 * analytic) << "walls " << layer << " high";
    EXPECT_LT(floor.sky, last_sky);
    last_sky = floor.sky;
  }
  EXPECT_GE(floor_updates, 5);
  EXPECT_LT(floor_updates, kSide / 2 + 1);  // half the layers or fewer
  EXPECT_GT(view.rays_cast(), 0u);
}

TEST(ViewFactor, AFaceRadiatesWithItsViewsOfTheSkyAndTheTable) {
  // One cell, 100 mm² of open surface at its own temperature (no half cell): its loss is convection plus
  // ε σ A [F_sky (T⁴ − T∞⁴) + F_table (T⁴ − T_bed⁴)].
  ThermalMesh mesh;
  mesh.voxel_size_mm = 1.0;
  ThermalCell c = cell_at({0.0, 0.0, 50.0}, 1000.0);
  c.open_area_mm2 = 100.0;
  mesh.cells.push_back(c);
  Material material = test_material();
  material.emissivity = 0.9;
  Environment env;
  env.ambient_c = 20.0;
  env.bed_temp_c = 80.0;
  env.convection_W_m2K = 7.0;
  PartModel model(mesh, material, env);
  std::vector<double> y(2, 0.0);
  model.birth(1, y);
  const double area = 100e-6, t = 200.0;
  const auto k4 = [](double temp_c) { return std::pow(temp_c + kKelvinOffset, 4); };
  const double es = 0.9 * kStefanBoltzmann_W_m2K4;
  const auto loss_of = [&] {
    double loss = 0.0;
    y[0] = t;
    model.rate(0, y.data(), loss);
    return loss;
  };
  const double convection = 7.0 * area * (t - 20.0);
  EXPECT_NEAR(loss_of(), convection + es * area * (k4(t) - k4(20.0)), 1e-12);
  // The floor of an open cubic box: a fifth of the sky, no table.
  model.add_view(0, area * (0.2 - 1.0), 0.0);
  const double box_floor = loss_of();
  EXPECT_NEAR(box_floor, convection + 0.2 * es * area * (k4(t) - k4(20.0)), 1e-12);
  // A wall's face at its foot: half sky, half table.
  model.add_view(0, area * (0.5 - 0.2), area * 0.5);
  EXPECT_NEAR(loss_of(), convection + es * area * (0.5 * (k4(t) - k4(20.0)) + 0.5 * (k4(t) - k4(80.0))),
              1e-12);
  // The box floor loses what convection and a fifth of the radiation take: at 200 °C about half a flat
  // plate's loss.
  const double plate = convection + es * area * (k4(t) - k4(20.0));
  EXPECT_NEAR(box_floor / plate, 0.49, 0.01);
}

}  // namespace
}  // namespace beadtwin::thermal
