// The variable-wall cylinder of seed 002 (Negrău, Pancu and Grebenișan 2023; scenarios/variable-wall-
// cylinder.yaml): the shipped scenario runs, lays the filament its constant feed delivers, and the wall it
// lays is as thick as the flow balance of the paper says, A = Q / v (eqs. 1, 2 and 12), around the circle.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <string>

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include "core/error.hpp"
#include "core/flow.hpp"
#include "core/units.hpp"
#include "scenarios/input/scenario.hpp"
#include "scenarios/run.hpp"
#include "sim/deposit.hpp"

namespace beadtwin::scenarios {
namespace {

// Seed 002 Table 1 at 220 °C: 1.75 mm filament fed at 2.31 mm/s; eq. 1.
const double kFlowMm3S = kPi * 1.75 * 1.75 / 4.0 * 2.31;  // 5.56 mm³/s
constexpr double kRadiusMm = 50.0;                        // program O2023, #10
constexpr double kLayerMm = 0.5;                          // #3
constexpr int kLayers = 40;                               // Z 0.5 to 20

using Feed = std::function<double(double angle_deg)>;  // axis feed, mm/min, at an angle of 0..180°

// The axis feed of program O2023 (Table 3): the step k = 1..90 of the upper semicircle runs from
// 180 - 2 (k - 1)° to 180 - 2k° at F = 100 + 5k, and the lower semicircle repeats the feeds mirrored (its
// step j from -2 (j - 1)° to -2j° at 555 - 5j), so the feed at |angle| is the same on both.
double paper_feed_mm_min(double angle_deg) {
  const int k = std::clamp(static_cast<int>(std::ceil((180.0 - angle_deg) / 2.0)), 1, 90);
  return 100.0 + 5.0 * k;
}

// The same filament at F267 all round (programs/o2023-constant-feed.nc).
double constant_feed_mm_min(double) {
  return 267.0;
}

// The wall's mean thickness A / h (eq. 2 over h: π h / 4 + b_p) that the flow balance A = Q / v gives,
// averaged over the angles [from, to] (degrees).
double balance_thickness_mm(double from_deg, double to_deg, const Feed& feed_mm_min) {
  constexpr int kSamples = 400;
  double sum = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    const double a = from_deg + (to_deg - from_deg) * (i + 0.5) / kSamples;
    sum += kFlowMm3S / (feed_mm_min(a) / 60.0) / kLayerMm;
  }
  return sum / kSamples;
}

// The filament fed while the head rises 0.5 mm at F1000 to start a layer, at 180°, spread as thickness over
// a wedge of `wedge_deg` at 180° (both semicircles' halves of it).
double rise_thickness_mm(double wedge_deg) {
  const double rise_mm3 = kFlowMm3S * kLayerMm / (1000.0 / 60.0);  // 0.17 mm³ a layer
  return rise_mm3 / (kLayerMm * kRadiusMm * 2.0 * wedge_deg * kPi / 180.0);
}

// How long the feed runs in the program: each layer's rise of 0.5 mm at F1000, then 2 x 90 chords of 2° at
// their feeds.
double melt_on_time_s(const Feed& feed_mm_min) {
  const double chord_mm = 2.0 * kRadiusMm * std::sin(kPi / 180.0);
  double layer_s = kLayerMm / (1000.0 / 60.0);
  for (int k = 1; k <= 90; ++k) layer_s += 2.0 * chord_mm / (feed_mm_min(181.0 - 2.0 * k) / 60.0);
  return kLayers * layer_s;
}

// The deposit's fill grid, as a run writes it to deposit.vdb.
openvdb::FloatGrid::Ptr read_fill(const std::filesystem::path& vdb) {
  openvdb::initialize();
  openvdb::io::File file(vdb.string());
  file.open();
  const openvdb::GridBase::Ptr grid = file.readGrid("fill");
  file.close();
  return openvdb::gridPtrCast<openvdb::FloatGrid>(grid);
}

// The wall's mean thickness in the deposit between the angles [from, to] (degrees, of |atan2(y, x)|: both
// semicircles) and the heights [z_from, z_to] (mm): the material there over the wall's area at the
// program's radius, R (to - from) (z_to - z_from), counted by voxel centre.
double deposit_thickness_mm(const openvdb::FloatGrid& fill, double voxel_mm, double from_deg, double to_deg,
                            double z_from, double z_to) {
  double volume = 0.0;
  for (auto it = fill.cbeginValueOn(); it; ++it) {
    const Eigen::Vector3d c = sim::voxel_center_mm(it.getCoord(), voxel_mm);
    const double a = std::abs(std::atan2(c.y(), c.x())) * 180.0 / kPi;
    if (a >= from_deg && a < to_deg && c.z() >= z_from && c.z() < z_to)
      volume += *it * voxel_mm * voxel_mm * voxel_mm;
  }
  const double both_halves = 2.0;
  return volume / (both_halves * kRadiusMm * (to_deg - from_deg) * kPi / 180.0 * (z_to - z_from));
}

struct Wall {
  double slow_mm = 0.0;  // at 180° (176-180°)
  double fast_mm = 0.0;  // at 0° (0-4°)
};

// Runs the shipped scenario into `dir` and measures its variants' walls. Small pictures of one sample a
// pixel, no skin, and a coarse thermal model without the cooldown keep it to a few seconds: the deposit,
// which this test measures, is the scenario's own.
std::map<std::string, Wall> run_and_measure(const std::filesystem::path& dir, RunResult& result) {
  const Scenario sc = load_scenario(
      std::filesystem::path(BEADTWIN_SOURCE_DIR) / "scenarios" / "data" / "variable-wall-cylinder.yaml",
      {parse_setting("render.width=160"), parse_setting("render.height=100"),
       parse_setting("render.samples=1"), parse_setting("output.skin=none"),
       parse_setting("thermal.cells_across=1"), parse_setting("thermal.cell_length=20 mm"),
       parse_setting("thermal.cooldown=0")});
  RunOptions o;
  o.out_dir = dir;
  std::filesystem::remove_all(o.out_dir);
  result = run_scenario(sc, o);
  std::map<std::string, Wall> walls;
  for (const VariantResult& v : result.variants) {
    const openvdb::FloatGrid::Ptr fill = read_fill(o.out_dir / v.deposit_file);
    const double s = v.variant->output.voxel_size_mm;
    // The 3rd to the 38th layer: clear of the first ones on the table and of the rounded top.
    walls[v.name] = {deposit_thickness_mm(*fill, s, 176.0, 180.0, 1.0, 19.0),
                     deposit_thickness_mm(*fill, s, 0.0, 4.0, 1.0, 19.0)};
  }
  return walls;
}

// The paper's program lays a wall five times thicker at 180° (F105-F110) than at 0° (F545-F550), each as
// thick as the flow balance says; the constant-feed variant, the same filament at F267, a uniform wall.
// The 180° wedge also holds the filament fed as the head rises to each new layer there (0.05 mm of
// thickness).
//
// Tolerance 1.5 %: the deposit conserves each move's volume and lays it along the move, so what is left is
// how the measurement counts voxels, by their centres, at the two ends of a wedge 3.5 mm long on each
// semicircle at 0.25 mm voxels, and the material the deposit pushes on from full voxels into free
// neighbours where beads meet (the four walls measure within 0.4 %).
TEST(VariableWall, WallFollowsTheFlowBalanceOfSeed002) {
  RunResult r;
  const auto walls = run_and_measure(std::filesystem::temp_directory_path() / "beadtwin_variable_wall", r);
  EXPECT_TRUE(r.passed) << "the scenario's gates";
  const std::map<std::string, Feed> feeds = {{"paper-feed", paper_feed_mm_min},
                                             {"constant-feed", constant_feed_mm_min}};
  ASSERT_EQ(r.variants.size(), feeds.size());
  for (const VariantResult& v : r.variants) {
    SCOPED_TRACE(v.name);
    const Feed& feed = feeds.at(v.name);
    const Metrics& m = v.metrics;
    EXPECT_EQ(m.layers, kLayers);
    EXPECT_FALSE(v.images.empty());
    // The program commands the constant feed for as long as it prints (eq. 1): Q times that time.
    EXPECT_NEAR(m.commanded_volume_mm3 / (kFlowMm3S * melt_on_time_s(feed)), 1.0, 1e-3);
    // What is commanded is laid.
    EXPECT_NEAR(m.deposited_volume_mm3 / m.commanded_volume_mm3, 1.0, 0.01);
    // The wall at 180° and at 0°, against the flow balance at the feeds there: the paper's F105-F110 and
    // F545-F550 give 6.25 mm and 1.22 mm; F267 gives 2.50 mm all round (2.54 mm with the rise at 180°).
    const Wall& wall = walls.at(v.name);
    const double slow = balance_thickness_mm(176.0, 180.0, feed) + rise_thickness_mm(4.0);
    const double fast = balance_thickness_mm(0.0, 4.0, feed);
    EXPECT_NEAR(wall.slow_mm / slow, 1.0, 0.015) << wall.slow_mm << " mm against " << slow << " mm";
    EXPECT_NEAR(wall.fast_mm / fast, 1.0, 0.015) << wall.fast_mm << " mm against " << fast << " mm";
  }
  EXPECT_GT(walls.at("paper-feed").slow_mm, 4.5 * walls.at("paper-feed").fast_mm) << "thicker where slower";
}

// The machine file holds the paper's head: 0.8 mm nozzle, 1.75 mm filament fed at 2.31 mm/s (Table 1),
// M23/M24 feed and M27/M28 heating, no roller.
TEST(VariableWall, MachineHoldsThePapersHead) {
  const Scenario sc = load_scenario(std::filesystem::path(BEADTWIN_SOURCE_DIR) / "scenarios" / "data" /
                                    "variable-wall-cylinder.yaml");
  const Machine& m = sc.variants.at(0).machine;
  EXPECT_EQ(m.extruder.kind, ExtruderKind::kFilament);
  EXPECT_DOUBLE_EQ(m.extruder.filament_diameter_mm, 1.75);
  EXPECT_DOUBLE_EQ(m.extruder.constant_feed_mm_s, 2.31);
  EXPECT_DOUBLE_EQ(m.nozzle_diameter_mm, 0.8);
  EXPECT_DOUBLE_EQ(m.roller_width_mm, 0.0);
  EXPECT_EQ(m.dialect.melt_on, "M23");
  EXPECT_EQ(m.dialect.melt_off, "M24");
  EXPECT_EQ(m.dialect.heat_on, "M27");
  EXPECT_EQ(m.dialect.heat_off, "M28");
  EXPECT_FALSE(m.dialect.inches);
  EXPECT_DOUBLE_EQ(sc.variants.at(0).material.deposition_temp_c, 220.0);  // Table 1
}

// A constant feed is a filament drive's, switched by melt codes: anything else is an input error at the key.
TEST(VariableWall, ConstantFeedNeedsAFilamentDriveAndMeltCodes) {
  const auto error_key = [](const std::string& extruder, const std::string& melt_on) {
    const std::string text =
        "name: bad\nunits: {length: mm}\nmaterial: pla\n"
        "machine: {name: m, kind: robot, extruder: {" +
        extruder + "}, gcode: {units: mm, melt_on: " + melt_on +
        "}}\n"
        "sections:\n"
        "  - {name: w, layers: 1, layer_height: 0.5, bead_width: 1, speed: 10,\n"
        "     outline: {points: [[0, 0], [10, 0]], closed: false}}\n";
    try {
      (void)load_scenario_text(text, "bad.yaml");
    } catch (const InputError& e) {
      return e.key();
    }
    return std::string("no error");
  };
  EXPECT_EQ(error_key("kind: filament, filament_diameter: 1.75, constant_feed: 2.31", "M23"), "no error");
  EXPECT_EQ(error_key("kind: gear_pump, displacement: 1, constant_feed: 2.31", "M23"),
            "machine.extruder.constant_feed");
  EXPECT_EQ(error_key("kind: filament, filament_diameter: 1.75, constant_feed: 2.31", "none"),
            "machine.extruder.constant_feed");
}

}  // namespace
}  // namespace beadtwin::scenarios
