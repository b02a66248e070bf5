// Tests of the heat solve's history recorder (thermal/history.hpp): the layers' volume-weighted mean
// temperatures at every sample time, every cell's temperature at the snapshot times, read from the state at
// the end of a step or, within it, from the state the integrator interpolates.
#include "thermal/history.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include "tests/thermal/test_meshes.hpp"

namespace beadtwin::thermal {
namespace {

// Three cells: two in layer 0 (100 and 300 mm³), one in layer 1; and one outside the toolpath's layers.
ThermalMesh three_cells() {
  ThermalMesh mesh;
  mesh.cells.push_back(cell_at({0.0, 0.0, 0.0}, 100.0, 0.0, 0));
  mesh.cells.push_back(cell_at({1.0, 0.0, 0.0}, 300.0, 0.0, 0));
  mesh.cells.push_back(cell_at({0.0, 0.0, 1.0}, 200.0, 5.0, 1));
  mesh.cells.push_back(cell_at({0.0, 0.0, 2.0}, 200.0, 5.0, -1));
  return mesh;
}

std::vector<std::uint32_t> one_to_one(std::size_t cells) {
  std::vector<std::uint32_t> model_of(cells + 1);
  std::iota(model_of.begin(), model_of.end(), 0u);
  return model_of;
}

TEST(HistoryRecorder, SamplesTheBornCellsOfEachLayerEveryIntervalWeightedByVolume) {
  const ThermalMesh mesh = three_cells();
  HeatOptions options;
  options.sample_interval_s = 2.0;
  HistoryRecorder history(mesh, 2, 0.0, 10.0, options);
  const std::vector<std::uint32_t> model_of = one_to_one(4);
  history.index(model_of);
  std::vector<double> asked;
  const auto state_at = [&](double t) {
    asked.push_back(t);
    return std::vector<double>{t, 2.0 * t, 100.0, 100.0};
  };
  // A step from 0 to 3 s with the first two cells born: samples at 0 and 2 s, from the interpolant.
  const std::vector<double> at_3 = {3.0, 6.0, 100.0, 100.0};
  history.record_until(3.0, at_3, 2, 2, state_at);
  EXPECT_EQ(asked, (std::vector<double>{0.0, 2.0}));
  // A step to 4 s with every cell born: the sample at 4 s from the state at its end.
  const std::vector<double> at_4 = {4.0, 8.0, 50.0, 100.0};
  history.record_until(4.0, at_4, 4, 4, state_at);
  EXPECT_EQ(asked.size(), 2u);
  HeatResult result;
  history.take(result);
  EXPECT_EQ(result.sample_times_s, (std::vector<double>{0.0, 2.0, 4.0}));
  ASSERT_EQ(result.layer_temp_c.size(), 2u);  // the cell outside the layers counts nowhere
  // Layer 0: (100 T + 300 · 2T) / 400 = 1.75 T.
  EXPECT_EQ(result.layer_temp_c[0], (std::vector<float>{0.0f, 3.5f, 7.0f}));
  ASSERT_EQ(result.layer_temp_c[1].size(), 3u);
  EXPECT_TRUE(std::isnan(result.layer_temp_c[1][0]));  // not born yet
  EXPECT_TRUE(std::isnan(result.layer_temp_c[1][1]));
  EXPECT_EQ(result.layer_temp_c[1][2], 50.0f);
  EXPECT_TRUE(result.snapshots.empty());
}

TEST(HistoryRecorder, TakesSnapshotsInTimeOrderClampedToTheSimulatedSpan) {
  const ThermalMesh mesh = three_cells();
  HeatOptions options;
  options.sample_interval_s = 100.0;
  options.snapshot_times_s = {7.0, -5.0, 1.5};
  HistoryRecorder history(mesh, 2, 0.0, 10.0, options);
  const std::vector<std::uint32_t> model_of = one_to_one(4);
  history.index(model_of);
  const auto state_at = [](double t) { return std::vector<double>{t, t, t, t}; };
  history.record_until(2.0, std::vector<double>{2.0, 2.0, 2.0, 2.0}, 3, 3, state_at);
  history.record_until(7.0, std::vector<double>{70.0, 70.0, 70.0, 70.0}, 4, 4, state_at);
  HeatResult result;
  history.take(result);
  ASSERT_EQ(result.snapshots.size(), 3u);
  EXPECT_EQ(result.snapshots[0].time_s, 0.0);  // -5 s clamped to the start
  EXPECT_EQ(result.snapshots[0].request, 1u);
  EXPECT_EQ(result.snapshots[1].time_s, 1.5);
  EXPECT_EQ(result.snapshots[1].request, 2u);
  EXPECT_EQ(result.snapshots[1].temp_c[0], 1.5f);
  EXPECT_EQ(result.snapshots[1].temp_c[2], 1.5f);
  EXPECT_TRUE(std::isnan(result.snapshots[1].temp_c[3]));  // not born by then
  EXPECT_EQ(result.snapshots[2].time_s, 7.0);
  EXPECT_EQ(result.snapshots[2].temp_c[3], 70.0f);  // at the step's end: its state
}

TEST(HistoryRecorder, ReadsALumpedCellsTemperatureForEachOfItsMeshCells) {
  const ThermalMesh mesh = three_cells();
  HeatOptions options;
  options.sample_interval_s = 1.0;
  options.snapshot_times_s = {1.0};
  HistoryRecorder history(mesh, 2, 1.0, 10.0, options);
  const std::vector<std::uint32_t> model_of = {0, 0, 1, 2, 3};  // cells 0 and 1 lumped
  history.index(model_of);
  const auto state_at = [](double) { return std::vector<double>{}; };
  history.record_until(1.0, std::vector<double>{80.0, 60.0, 40.0}, 4, 3, state_at);
  HeatResult result;
  history.take(result);
  ASSERT_EQ(result.snapshots.size(), 1u);
  EXPECT_EQ(result.snapshots[0].temp_c, (std::vector<float>{80.0f, 80.0f, 60.0f, 40.0f}));
  EXPECT_EQ(result.layer_temp_c[0], (std::vector<float>{80.0f}));
  EXPECT_EQ(result.layer_temp_c[1], (std::vector<float>{60.0f}));
}

}  // namespace
}  // namespace beadtwin::thermal
