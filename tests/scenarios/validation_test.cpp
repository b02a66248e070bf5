// The model held against published evidence (docs/validation.md): the shipped Compton wall
// (scenarios/data/compton-wall.yaml) as a thermal camera would see it, the layer time at which its interfaces
// stop healing, and the layer time it was printed at.
//
// No measured temperature history or interlayer strength of a large-format wall could be read here (the
// search is in docs/validation.md), so two comparisons hold the model to stand-ins, each named as such:
//  - camera spots on the wall's side against the paper's own 1-D model of the wall, which Compton et al.
//    report agreeing with their IR measurements (not a measurement: a model recomputed from the paper's
//    inputs);
//  - the longest layer time that still heals against the layer time at which the substrate's surface has
//    cooled to T_g as the next layer lands: the rule by which Corum et al. 2026 explain where the interlayer
//    strength of single-bead CF-ABS walls falls (their numbers were not reachable, only the rule).
// The third holds the model's layer-time window against the layer time the wall was printed at
// (tests/data/validation/printable_layer_times.csv).
//
// Each comparison passes only within its tolerance (docs/validation.md) and is skipped, with its numbers,
// where the model misses it: the suite then says which comparisons hold instead of failing on a known gap.
// With BEADTWIN_VALIDATION_OUT naming a folder, each also writes what it compared there as CSV, which
// tools/validation_plots.py draws.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "scenarios/input/scenario.hpp"
#include "scenarios/variant_stages.hpp"
#include "sim/deposit.hpp"
#include "tests/read_file.hpp"
#include "tests/scenarios/compton_wall.hpp"
#include "thermal/thermal.hpp"
#include "thermal/wall_1d.hpp"

namespace beadtwin::scenarios {
namespace {

using testing::at_time;
using testing::first_deposit;
using testing::keep_layers;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The Compton wall's variant `name` (baseline: beadtwin's material; compton-conductivity: the paper's),
// cut to its first `layers` layers.
Variant compton_variant(std::string_view name, int layers) {
  Scenario sc = testing::compton_scenario();
  for (Variant& v : sc.variants)
    if (v.name == name) {
      keep_layers(v, layers);
      return v;
    }
  throw InternalError(fmt::format("the Compton wall has no variant {}", name));
}

// The wall's length, mm: its one bead per layer.
double wall_length_mm(const Variant& v) {
  return (v.sections.at(0).outline_path.front() - v.sections.at(0).outline_path.back()).norm();
}

// The time from the first layer's bead to the second's, s: the bead along the wall and the travel back.
double layer_time_s(const Toolpath& tp) {
  return first_deposit(tp, 1).start_s - first_deposit(tp, 0).start_s;
}

// The wall printed at about `target_s` per layer: the head's speed along the wall set so that the bead and
// the travel back (as long as the shipped wall's) take that long.
void set_layer_time(Variant& v, double target_s) {
  Variant two = v;
  keep_layers(two, 2);
  const double length = wall_length_mm(v);
  const double travel_s = layer_time_s(variant_toolpath(two)) - length / v.sections.at(0).print_speed_mm_s;
  v.sections.at(0).print_speed_mm_s = length / (target_s - travel_s);
}

// A variant printed, deposited and solved as a run does it, with every cell's temperature kept every
// `snapshot_every_s` seconds (none when 0).
struct Solved {
  Toolpath toolpath;
  thermal::ThermalResult thermal;
};
Solved solve(const Variant& v, double snapshot_every_s = 0.0) {
  Solved s{variant_toolpath(v), {}};
  const sim::Deposit deposit = deposit_variant(v, s.toolpath, {});
  thermal::ThermalInput in = thermal_input(v, s.toolpath, deposit, {}, nullptr);
  in.heat.snapshot_times_s.clear();
  if (snapshot_every_s > 0.0)
    for (double t = 0.0; t <= s.toolpath.total_time_s() + in.heat.cooldown_s; t += snapshot_every_s)
      in.heat.snapshot_times_s.push_back(t);
  s.thermal = thermal::solve_thermal(in);
  return s;
}

// What a thermal camera reads of the substrate where the next layer lands, °C: the surface of the layer
// below just before it is covered, as the model reports it (the substrate cell's face, behind its half
// cell), area-weighted over the layer.
double substrate_as_camera_reads_c(const thermal::FusionSummary& landing_layer) {
  return landing_layer.surface.mean_c;
}

// The cell a camera facing the wall's side (the -y side) sees at `x_mm` along layer `layer`: of the layer's
// cells in the strip nearest that side, the one whose centre is nearest x.
std::size_t camera_cell(const thermal::ThermalMesh& mesh, int layer, double x_mm) {
  double side_y = std::numeric_limits<double>::infinity();
  for (const thermal::ThermalCell& c : mesh.cells)
    if (c.layer == layer) side_y = std::min(side_y, c.centroid_mm.y());
  std::size_t best = mesh.cells.size();
  for (std::size_t i = 0; i < mesh.cells.size(); ++i) {
    const thermal::ThermalCell& c = mesh.cells[i];
    if (c.layer != layer || c.centroid_mm.y() > side_y + 1e-3 * mesh.voxel_size_mm) continue;
    if (best == mesh.cells.size() ||
        std::abs(c.centroid_mm.x() - x_mm) < std::abs(mesh.cells[best].centroid_mm.x() - x_mm))
      best = i;
  }
  if (best == mesh.cells.size()) throw InternalError(fmt::format("layer {} has no cells", layer));
  return best;
}

// What the camera reads of `cell` in `snapshot`, °C: the cell's mean temperature (a snapshot holds the
// cells' temperatures, not their faces'), a few kelvin above the surface the camera sees.
double side_as_camera_reads_c(const thermal::TemperatureSnapshot& snapshot, std::size_t cell) {
  return snapshot.temp_c.at(cell);
}

// A CSV file of what a comparison compared, in $BEADTWIN_VALIDATION_OUT; nothing when it is not set.
void write_csv(const std::string& name, const std::string& header, const std::vector<std::string>& rows) {
  const char* dir = std::getenv("BEADTWIN_VALIDATION_OUT");
  if (dir == nullptr || *dir == '\0') return;
  std::filesystem::create_directories(dir);
  std::ofstream out(std::filesystem::path(dir) / name);
  out << header << '\n';
  for (const std::string& r : rows) out << r << '\n';
}

// The paper's own 1-D model of the wall `tp`, which Compton et al. report agreeing with their IR
// measurements: every layer a slab of the bead's width along the whole wall, landing at once when its first
// bead does, losing heat from its two sides (and the top layer from its top), with the paper's inputs (the
// shipped variant compton-conductivity pins its conductivity, 0.17 W/mK isotropic, emissivity, deposition,
// air, table and convection; density and a constant specific heat are pinned here), until `end_s`.
thermal::Wall1dResult papers_one_d_model(const Toolpath& tp, double end_s) {
  Variant paper = compton_variant("compton-conductivity", static_cast<int>(tp.layers.size()));
  paper.material.density_kg_m3 = 1140.0;
  paper.material.specific_heat_J_kgK = 1640.0;
  paper.material.specific_heat_by_temp.clear();
  const double length = wall_length_mm(paper), width = paper.sections.at(0).bead_width_mm;
  std::vector<thermal::Wall1dLayer> stack;
  for (std::size_t i = 0; i < tp.layers.size(); ++i) {
    thermal::Wall1dLayer in;
    in.z_top_mm = tp.layers[i].z_mm;
    in.height_mm = tp.layers[i].height_mm;
    in.start_s = in.end_s = first_deposit(tp, i).start_s;
    in.area_mm2 = width * length;
    in.perimeter_mm = 2.0 * length;
    stack.push_back(in);
  }
  thermal::Wall1dOptions o;
  o.cooldown_s = end_s - stack.back().end_s;
  o.sample_interval_s = 1.0;
  // The paper's model resolves the height only: each node is one temperature across the wall's width and
  // its sides lose heat at it. (Through half the 20 mm width at 0.17 W/mK, as beadtwin's own 1-D reference
  // has it, the sides lose about half as much and this curve runs 13 K hotter: docs/validation.md.)
  o.side_half_cell = false;
  return thermal::solve_wall_1d(stack, paper.material, paper.machine.environment, o);
}

struct Agreement {
  double rms_K = 0.0, max_K = 0.0;
  std::size_t samples = 0;
};

// Compton et al. imaged the middle of the wall's layers 1, 15 and 30 with an IR camera. Stand-in for their IR
// data: their 1-D model of the same wall (papers_one_d_model). The camera spots are compared from the spot's
// birth (and one birth interval, while its group lands) to ten minutes after it, each column of the 1-D
// model shifted to the time its own bead landed, as tests/scenarios/compton_wall_test.cpp does for the
// layers' means. Tolerance: 10 K RMS and 15 K at most, as for a measured IR history.
TEST(Validation, ComptonWallCameraSpotsAgainstThePapersOneDModel) {
  constexpr int kLayers = 40;  // layer 30 and ten more on top of it
  constexpr double kSpotWindowS = 600.0, kSnapshotEveryS = 5.0;
  const Variant v = compton_variant("baseline", kLayers);
  const Solved s = solve(v, kSnapshotEveryS);
  const thermal::HeatResult& heat = s.thermal.heat;
  const thermal::Wall1dResult one_d = papers_one_d_model(s.toolpath, heat.end_time_s);
  const double middle_mm = 0.5 * wall_length_mm(v);

  Agreement a;
  double sum2 = 0.0;
  std::vector<std::string> rows;
  for (const int layer : {0, 14, 29}) {  // the paper's layers 1, 15 and 30
    const std::size_t cell = camera_cell(s.thermal.mesh, layer, middle_mm);
    const double born = s.thermal.mesh.cells[cell].birth_s;
    const double shift = born - first_deposit(s.toolpath, static_cast<std::size_t>(layer)).start_s;
    EXPECT_NEAR(s.thermal.mesh.cells[cell].centroid_mm.x(), middle_mm, v.sections[0].bead_width_mm);
    for (const thermal::TemperatureSnapshot& snap : heat.snapshots) {
      if (snap.time_s < born + heat.birth_interval_s || snap.time_s > born + kSpotWindowS) continue;
      const double model = side_as_camera_reads_c(snap, cell);
      const double paper = at_time(one_d.sample_times_s, one_d.layer_temp_c[static_cast<std::size_t>(layer)],
                                   snap.time_s - shift);
      ASSERT_TRUE(std::isfinite(model) && std::isfinite(paper)) << "layer " << layer << " at " << snap.time_s;
      a.max_K = std::max(a.max_K, std::abs(model - paper));
      sum2 += (model - paper) * (model - paper);
      ++a.samples;
      rows.push_back(fmt::format("{},{:.1f},{:.2f},{:.2f}", layer + 1, snap.time_s - born, model, paper));
    }
  }
  a.rms_K = std::sqrt(sum2 / static_cast<double>(a.samples));
  write_csv("camera_spots.csv", "paper_layer,time_since_landing_s,model_c,papers_1d_model_c", rows);
  RecordProperty("rms_K", fmt::format("{:.2f}", a.rms_K));
  RecordProperty("max_K", fmt::format("{:.2f}", a.max_K));
  // Every spot from its landing to ten minutes on, every 5 s: three times 117 or so.
  EXPECT_GT(a.samples, 3u * 110u);
  if (a.rms_K > 10.0 || a.max_K > 15.0)
    GTEST_SKIP() << fmt::format(
        "camera spots of layers 1, 15, 30 against the paper's 1-D model: {:.1f} K RMS, {:.1f} K at most over "
        "{} samples (tolerance 10 K RMS, 15 K at most)",
        a.rms_K, a.max_K, a.samples);
}

// The wall at a range of layer times: per layer time, what the middle layer's landing interfaces saw.
struct SweepPoint {
  double layer_time_s = 0.0;
  double substrate_c = 0.0;  // the substrate's surface as the layer landed (substrate_as_camera_reads_c)
  double healing = 0.0;      // their area-weighted mean degree of healing
  double slump = 0.0;        // the most one slumped, over what is allowed (above 1: too hot)
};

// 16 layers at layer times from the shipped 40 s to 300 s; layer 13 (index 12), the last with three layers on
// top of it, 49 mm above the table: at 150 s its substrate and healing are within 0.4 K and 0.005 of layer
// 29 of a 32-layer wall's, so it stands for a tall wall's layers.
std::vector<SweepPoint> layer_time_sweep() {
  constexpr int kLayers = 16;
  constexpr std::size_t kLayer = 12;
  std::vector<SweepPoint> points;
  std::vector<std::string> rows;
  for (const double target_s : {40.0, 60.0, 80.0, 100.0, 120.0, 150.0, 180.0, 240.0, 300.0}) {
    Variant v = compton_variant("baseline", kLayers);
    set_layer_time(v, target_s);
    const Solved s = solve(v);
    const thermal::FusionSummary& landing = s.thermal.layers.at(kLayer);
    points.push_back({layer_time_s(s.toolpath), substrate_as_camera_reads_c(landing), landing.healing_mean,
                      landing.slump_ratio_max});
    rows.push_back(fmt::format("{:.2f},{:.2f},{:.4f},{:.4g}", points.back().layer_time_s,
                               points.back().substrate_c, points.back().healing, points.back().slump));
  }
  write_csv("layer_time_sweep.csv", "layer_time_s,substrate_c,healing_mean,slump_ratio_max", rows);
  return points;
}

// The layer time at which `value` crosses `level` (the first crossing), linear between the sweep's points;
// NaN when it does not cross within the sweep.
double crossing(const std::vector<SweepPoint>& points, double SweepPoint::*value, double level) {
  for (std::size_t k = 1; k < points.size(); ++k) {
    const double a = points[k - 1].*value - level, b = points[k].*value - level;
    if (a == 0.0) return points[k - 1].layer_time_s;
    if ((a < 0.0) != (b < 0.0) || b == 0.0)
      return points[k - 1].layer_time_s + a / (a - b) * (points[k].layer_time_s - points[k - 1].layer_time_s);
  }
  return kNaN;
}

// Corum et al. 2026 printed single-bead CF-ABS walls at a range of layer times and found the interlayer
// strength falling fast once the layer time exceeds the time the layer below takes to cool below T_g: their
// own definition of the critical layer time. Their numbers could not be read, so the comparison holds the
// model to the rule on the Compton wall: the longest layer time at which the middle layer still heals as
// required, within ±20 % of the layer time at which its substrate's surface has cooled to T_g as it lands.
TEST(Validation, HealingLayerTimeAgainstTheGlassTransitionRule) {
  const std::vector<SweepPoint> sweep = layer_time_sweep();
  const Material m = compton_variant("baseline", 1).material;
  // Hotter and better healed at short layer times, colder and less at long ones.
  EXPECT_GT(sweep.front().substrate_c, sweep.back().substrate_c);
  EXPECT_GE(sweep.front().healing, sweep.back().healing);
  const double at_tg_s = crossing(sweep, &SweepPoint::substrate_c, m.glass_transition_c);
  const double heals_s = crossing(sweep, &SweepPoint::healing, m.required_healing);
  RecordProperty("substrate_at_tg_layer_time_s", fmt::format("{:.1f}", at_tg_s));
  RecordProperty("healing_reaches_requirement_layer_time_s", fmt::format("{:.1f}", heals_s));
  const std::string numbers = fmt::format(
      "layer time with the substrate at T_g {:.0f} C as the layer lands: {:.1f} s; longest layer time "
      "healing "
      "to {:.2f}: {:.1f} s (NaN where not within {:.0f}..{:.0f} s)",
      m.glass_transition_c, at_tg_s, m.required_healing, heals_s, sweep.front().layer_time_s,
      sweep.back().layer_time_s);
  if (!std::isfinite(at_tg_s) || !std::isfinite(heals_s) || std::abs(heals_s / at_tg_s - 1.0) > 0.2)
    GTEST_SKIP() << numbers << "; tolerance ±20 %";
  SUCCEED() << numbers;
}

// The rows of tests/data/validation/printable_layer_times.csv of kind `kind`: (id, layer time s).
std::vector<std::pair<std::string, double>> printable_layer_times(std::string_view kind) {
  std::istringstream in(testing::read_file(std::filesystem::path(BEADTWIN_SOURCE_DIR) /
                                           "tests/data/validation/printable_layer_times.csv"));
  std::vector<std::pair<std::string, double>> rows;
  bool header = true;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line.front() == '#') continue;
    if (std::exchange(header, false)) continue;
    std::vector<std::string> cells;
    std::istringstream fields(line);
    for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
    if (cells.size() != 6) throw InternalError("printable_layer_times.csv: a row without 6 columns: " + line);
    if (cells[1] == kind) rows.emplace_back(cells[0], std::stod(cells[5]));
  }
  return rows;
}

// The wall was printed at 40 s per layer (Compton et al. 2017: the IR data of its layers 1, 15 and 30 were
// taken on it). Its layer-time window from the same sweep (what lies under a landing bead carries it, and
// healing as required) should hold that layer time.
TEST(Validation, ComptonWallWindowHoldsThePrintedLayerTime) {
  const auto printed = printable_layer_times("printed");
  ASSERT_EQ(printed.size(), 1u);
  ASSERT_EQ(printed[0].first, "compton2017");
  const std::vector<SweepPoint> sweep = layer_time_sweep();
  const Material m = compton_variant("baseline", 1).material;
  // Carried from this layer time on (+infinity: not within the sweep), healing up to the next (0: not even
  // at its shortest).
  double from_s = crossing(sweep, &SweepPoint::slump, 1.0);
  if (!(sweep.front().slump > 1.0)) from_s = 0.0;
  if (!std::isfinite(from_s)) from_s = std::numeric_limits<double>::infinity();
  double to_s = crossing(sweep, &SweepPoint::healing, m.required_healing);
  if (sweep.back().healing >= m.required_healing) to_s = std::numeric_limits<double>::infinity();
  if (!std::isfinite(to_s) && sweep.front().healing < m.required_healing) to_s = 0.0;
  RecordProperty("window_min_s", fmt::format("{:.1f}", from_s));
  RecordProperty("window_max_s", fmt::format("{:.1f}", to_s));
  const double printed_s = printed[0].second;
  if (!(from_s <= printed_s && printed_s <= to_s))
    GTEST_SKIP() << fmt::format(
        "the middle layer's window is {:.1f}..{:.1f} s (slump at most {:.2f} of a layer, healing {:.2f}); "
        "the "
        "wall was printed at {:.0f} s per layer",
        from_s, to_s, m.max_slump, m.required_healing, printed_s);
}

}  // namespace
}  // namespace beadtwin::scenarios
