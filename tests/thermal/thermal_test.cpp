// Tests of the thermal stage's entry (thermal/thermal.hpp): a print's deposit in, its mesh, heat solution,
// layer summaries and cell verdicts out, with the input's options reaching every step.
#include "thermal/thermal.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "tests/sim/lsam_beads.hpp"

namespace beadtwin::thermal {
namespace {

using testing::bead;
using testing::kBeadHeight;
using testing::timed;
using testing::travel;

constexpr double kLength = 120.0;

// Two beads along x, the second laid on the first after a travel of 12 m away and back (half a minute):
// two toolpath layers, the first cooling as the second lands.
Toolpath stacked_beads() {
  const double z0 = kBeadHeight, z1 = 2.0 * kBeadHeight;
  return timed({bead({0.0, 0.0, z0}, {kLength, 0.0, z0}, 0),
                travel({kLength, 0.0, z0}, {kLength, 6000.0, z1}),
                travel({kLength, 6000.0, z1}, {0.0, 0.0, z1}), bead({0.0, 0.0, z1}, {kLength, 0.0, z1}, 1)});
}

sim::Deposit deposit_of(const Toolpath& toolpath) {
  sim::DepositOptions options;
  options.voxel_size_mm = kBeadHeight / 4.0;
  return sim::deposit(toolpath, options);
}

ThermalInput input_for(const Toolpath& toolpath, const sim::Deposit& deposit) {
  ThermalInput in{
      .toolpath = toolpath, .deposit = deposit, .material = {}, .environment = {}, .mesh = {}, .heat = {}};
  in.material.deposition_temp_c = 230.0;
  in.environment.bed_temp_c = 80.0;
  in.mesh.cells_across = 1;
  in.mesh.cell_length_mm = 20.0;
  in.heat.birth_interval_s = 0.5;
  in.heat.cooldown_s = 120.0;
  in.heat.sample_interval_s = 2.0;
  return in;
}

TEST(ThermalStage, GivesWhatItsStepsGiveWithTheInputsOptions) {
  const Toolpath toolpath = stacked_beads();
  const sim::Deposit deposit = deposit_of(toolpath);
  ThermalInput in = input_for(toolpath, deposit);
  in.heat.snapshot_times_s = {toolpath.total_time_s(), 0.0};
  std::vector<double> reported;
  in.heat.progress = [&](double fraction) { reported.push_back(fraction); };
  const ThermalResult result = solve_thermal(in);

  // The mesh with the input's mesh options: 6 pieces of 20 mm, one strip and one slice, per bead.
  const ThermalMesh mesh = build_thermal_mesh(toolpath, deposit, in.mesh);
  ASSERT_EQ(result.mesh.cells.size(), 12u);
  ASSERT_EQ(result.mesh.cells.size(), mesh.cells.size());
  EXPECT_EQ(result.mesh.links.size(), mesh.links.size());

  // The heat solve with the input's heat options, to the end of the print plus the cooldown.
  HeatOptions quiet = in.heat;
  quiet.progress = {};
  const HeatResult heat =
      solve_heat(mesh, toolpath.layers.size(), toolpath.total_time_s(), in.material, in.environment, quiet);
  ASSERT_EQ(result.heat.interfaces.size(), heat.interfaces.size());
  ASSERT_FALSE(heat.interfaces.empty());
  for (std::size_t k = 0; k < heat.interfaces.size(); ++k) {
    EXPECT_EQ(result.heat.interfaces[k].substrate_c, heat.interfaces[k].substrate_c) << k;
    EXPECT_EQ(result.heat.interfaces[k].healing_integral, heat.interfaces[k].healing_integral) << k;
  }
  EXPECT_DOUBLE_EQ(result.heat.end_time_s, toolpath.total_time_s() + 120.0);
  EXPECT_EQ(result.heat.sample_times_s.size(), heat.sample_times_s.size());
  ASSERT_EQ(result.heat.snapshots.size(), 2u);
  EXPECT_EQ(result.heat.snapshots[0].request, 1u);  // in time order: t = 0 first
  EXPECT_EQ(result.heat.snapshots[1].request, 0u);
  ASSERT_FALSE(reported.empty());
  EXPECT_EQ(reported.back(), 1.0);

  // The summaries: per toolpath layer, with the layers' durations as printed; per cell.
  std::vector<double> durations;
  for (const ToolpathLayer& l : toolpath.layers) durations.push_back(l.duration_s());
  const std::vector<FusionSummary> layers =
      summarise_layers(mesh, heat, durations, in.material, in.environment.ambient_c);
  ASSERT_EQ(result.layers.size(), toolpath.layers.size());
  EXPECT_EQ(result.layers[0].interfaces, 0u);  // the first bead lands on the table
  EXPECT_EQ(result.layers[1].interfaces, heat.interfaces.size());
  EXPECT_EQ(result.layers[1].substrate.mean_c, layers[1].substrate.mean_c);
  // The same window (NaN, nothing bounding an end, counts as the same).
  const auto same = [](double x, double y) { return x == y || (std::isnan(x) && std::isnan(y)); };
  EXPECT_TRUE(same(result.layers[1].layer_time_min_s, layers[1].layer_time_min_s));
  EXPECT_TRUE(same(result.layers[1].layer_time_max_s, layers[1].layer_time_max_s));
  EXPECT_LT(result.layers[1].substrate.mean_c, in.material.deposition_temp_c - 20.0);  // it cooled
  EXPECT_TRUE(std::isfinite(result.layers[1].layer_time_max_s));
  ASSERT_EQ(result.cells.size(), mesh.cells.size());
  EXPECT_EQ(result.cells, cell_verdicts(mesh, heat));
  for (std::size_t i = 0; i < mesh.cells.size(); ++i)
    EXPECT_EQ(result.cells[i] == Verdict::kNoInterface, mesh.cells[i].layer == 0) << i;
}

// The program's nozzle temperature (Move::nozzle_c, M104/M109) is the beads' temperature: a program at
// 230 °C on a material whose file says 200 °C heals exactly as the material at 230 °C would; a second bead
// set 20 K hotter is born 20 K hotter, heals more, and the report's note says so.
TEST(ThermalStage, TheProgramsNozzleTemperatureIsTheBeadsTemperature) {
  const Toolpath plain = stacked_beads();
  const sim::Deposit deposit = deposit_of(plain);
  const ThermalResult from_file = solve_thermal(input_for(plain, deposit));  // the material at 230 °C
  ASSERT_FALSE(from_file.heat.interfaces.empty());
  for (const std::string& n : from_file.heat.notes) EXPECT_EQ(n.find("nozzle"), std::string::npos) << n;

  const auto program_at = [&](float first_c, float second_c) {
    Toolpath tp = plain;
    for (Move& m : tp.moves) m.nozzle_c = m.layer == 0 ? first_c : second_c;
    ThermalInput in = input_for(tp, deposit);
    in.material.deposition_temp_c = 200.0;  // the file's; the program's stands
    in.material.ranges = {{.key = "deposition_temp", .lo = 190.0, .hi = 210.0}};
    return solve_thermal(in);
  };
  const ThermalResult same = program_at(230.0f, 230.0f);
  ASSERT_EQ(same.heat.interfaces.size(), from_file.heat.interfaces.size());
  for (std::size_t k = 0; k < same.heat.interfaces.size(); ++k) {
    EXPECT_DOUBLE_EQ(same.heat.interfaces[k].healing_integral, from_file.heat.interfaces[k].healing_integral);
    EXPECT_DOUBLE_EQ(same.heat.interfaces[k].bead_c, 230.0);
  }
  EXPECT_DOUBLE_EQ(same.heat.energy_in_J, from_file.heat.energy_in_J);

  const ThermalResult hotter = program_at(230.0f, 250.0f);
  double sum_same = 0.0, sum_hotter = 0.0;
  for (std::size_t k = 0; k < hotter.heat.interfaces.size(); ++k) {
    EXPECT_DOUBLE_EQ(hotter.heat.interfaces[k].bead_c, 250.0);
    EXPECT_GT(hotter.heat.interfaces[k].healing_integral, same.heat.interfaces[k].healing_integral) << k;
    sum_same += same.heat.interfaces[k].healing_integral;
    sum_hotter += hotter.heat.interfaces[k].healing_integral;
  }
  EXPECT_GT(sum_hotter, 1.5 * sum_same);
  EXPECT_GT(hotter.heat.energy_in_J, same.heat.energy_in_J);
  bool noted = false;
  for (const std::string& n : hotter.heat.notes)
    noted = noted ||
            (n.find("nozzle temperature") != std::string::npos && n.find("230-250") != std::string::npos);
  EXPECT_TRUE(noted);
}

TEST(ThermalStage, BadOptionsAreInputErrorsNamingTheKey) {
  const Toolpath toolpath = stacked_beads();
  const sim::Deposit deposit = deposit_of(toolpath);
  ThermalInput even_strips = input_for(toolpath, deposit);
  even_strips.mesh.cells_across = 2;
  EXPECT_THROW(solve_thermal(even_strips), InputError);
  ThermalInput no_tolerance = input_for(toolpath, deposit);
  no_tolerance.heat.rel_tol = 0.0;
  try {
    solve_thermal(no_tolerance);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("thermal.rel_tol"), std::string::npos) << e.what();
  }
}

TEST(ThermalStage, ADepositWithoutMaterialGivesAnEmptyMeshAndSolution) {
  const Toolpath toolpath = timed({travel({0.0, 0.0, kBeadHeight}, {kLength, 0.0, kBeadHeight})});
  const sim::Deposit deposit = deposit_of(toolpath);
  const ThermalResult result = solve_thermal(input_for(toolpath, deposit));
  EXPECT_TRUE(result.mesh.cells.empty());
  EXPECT_TRUE(result.heat.interfaces.empty());
  EXPECT_TRUE(result.cells.empty());
}

}  // namespace
}  // namespace beadtwin::thermal
