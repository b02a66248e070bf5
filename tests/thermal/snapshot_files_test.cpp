// Tests of the temperature snapshot files (thermal/snapshot_files.hpp): read back, they hold what the solver
// kept, where the cells are.
#include "thermal/snapshot_files.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <openvdb/openvdb.h>

#include "tests/read_file.hpp"
#include "tests/sim/lsam_beads.hpp"

namespace beadtwin::thermal {
namespace {

using testing::read_file;

using testing::bead;
using testing::kBeadHeight;
using testing::timed;
using testing::travel;

struct Solved {
  ThermalMesh mesh;
  HeatResult heat;
};

// Two stacked LSAM beads, a snapshot while the second is being laid and one after both.
Solved two_beads() {
  const double z0 = kBeadHeight, z1 = 2 * kBeadHeight;
  const Toolpath tp = timed({bead({0, 0, z0}, {300, 0, z0}, 0), travel({300, 0, z0}, {0, 0, z1}),
                             bead({0, 0, z1}, {300, 0, z1}, 1)});
  sim::DepositOptions d;
  d.voxel_size_mm = kBeadHeight / 4;
  Solved s;
  s.mesh = build_thermal_mesh(tp, sim::deposit(tp, d));
  HeatOptions o;
  o.cooldown_s = 60;
  o.birth_interval_s = 0.25;  // several groups along each bead
  const double middle = 0.5 * (tp.layers[1].start_s + tp.layers[1].end_s);
  o.snapshot_times_s = {middle, tp.total_time_s() + 30};
  s.heat = solve_heat(s.mesh, tp.layers.size(), tp.total_time_s(), Material{}, Environment{}, o);
  return s;
}

TEST(SnapshotFiles, SolverKeepsTheCellsBornByThen) {
  const Solved s = two_beads();
  ASSERT_EQ(s.heat.snapshots.size(), 2u);
  const TemperatureSnapshot& mid = s.heat.snapshots[0];
  std::size_t born = 0;
  for (std::size_t i = 0; i < s.mesh.cells.size(); ++i) {
    const bool expected = s.mesh.cells[i].birth_s <= mid.time_s + s.heat.birth_interval_s;
    if (!std::isnan(mid.temp_c[i])) ++born;
    if (s.mesh.cells[i].birth_s < mid.time_s - s.heat.birth_interval_s) {
      EXPECT_FALSE(std::isnan(mid.temp_c[i])) << i;
    }
    if (!expected) {
      EXPECT_TRUE(std::isnan(mid.temp_c[i])) << i;
    }
  }
  EXPECT_GT(born, 0u);
  EXPECT_LT(born, s.mesh.cells.size());  // half of the top bead is not laid yet
  for (const float t : s.heat.snapshots[1].temp_c) {
    EXPECT_FALSE(std::isnan(t));
    EXPECT_LT(t, Material{}.deposition_temp_c);
    EXPECT_GT(t, Environment{}.ambient_c);
  }
}

TEST(SnapshotFiles, VdbHoldsEachVoxelsCellTemperature) {
  const Solved s = two_beads();
  const auto path = std::filesystem::temp_directory_path() / "beadtwin_snapshot.vdb";
  write_temperature_vdb(s.mesh, s.heat.snapshots[0], path);
  openvdb::initialize();
  openvdb::io::File file(path.string());
  file.open();
  EXPECT_NEAR(file.getMetadata()->metaValue<double>("time_s"), s.heat.snapshots[0].time_s, 1e-9);
  const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("temperature_c"));
  file.close();
  ASSERT_TRUE(grid);
  std::size_t checked = 0;
  openvdb::FloatGrid::ConstAccessor at = grid->getConstAccessor();
  for (auto it = s.mesh.cell_grid->cbeginValueOn(); it; ++it) {
    const float expected = s.heat.snapshots[0].temp_c[static_cast<std::size_t>(*it)];
    if (std::isnan(expected)) {
      EXPECT_FALSE(at.isValueOn(it.getCoord()));
    } else {
      ASSERT_TRUE(at.isValueOn(it.getCoord()));
      EXPECT_EQ(at.getValue(it.getCoord()), expected);
      ++checked;
    }
  }
  EXPECT_EQ(static_cast<openvdb::Index64>(checked), grid->activeVoxelCount());
  std::filesystem::remove(path);
}

TEST(SnapshotFiles, VtpPointsAreTheBornCellsCentroids) {
  const Solved s = two_beads();
  const auto path = std::filesystem::temp_directory_path() / "beadtwin_snapshot.vtp";
  const TemperatureSnapshot& snap = s.heat.snapshots[1];
  const std::size_t n = write_temperature_vtp(s.mesh, snap, path);
  EXPECT_EQ(n, s.mesh.cells.size());
  const std::string text = read_file(path);
  EXPECT_NE(text.find("<VTKFile type=\"PolyData\""), std::string::npos);
  EXPECT_NE(text.find("NumberOfPoints=\"" + std::to_string(n) + "\""), std::string::npos);
  // The appended data: points first (3 floats each), then the temperatures.
  const std::size_t start = text.find("<AppendedData encoding=\"raw\">\n_");
  ASSERT_NE(start, std::string::npos);
  const char* data = text.data() + start + std::strlen("<AppendedData encoding=\"raw\">\n_");
  std::uint64_t bytes = 0;
  std::memcpy(&bytes, data, 8);
  ASSERT_EQ(bytes, 3 * n * sizeof(float));
  std::vector<float> points(3 * n);
  std::memcpy(points.data(), data + 8, bytes);
  const char* temps = data + 8 + bytes;
  std::memcpy(&bytes, temps, 8);
  ASSERT_EQ(bytes, n * sizeof(float));
  std::vector<float> t(n);
  std::memcpy(t.data(), temps + 8, bytes);
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_NEAR(points[3 * i], s.mesh.cells[i].centroid_mm.x(), 1e-3);
    EXPECT_NEAR(points[3 * i + 2], s.mesh.cells[i].centroid_mm.z(), 1e-3);
    EXPECT_EQ(t[i], snap.temp_c[i]);
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace beadtwin::thermal
