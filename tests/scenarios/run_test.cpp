// The whole pipeline on a small scenario: every stage runs for real and the reports hold the documented keys.
#include "scenarios/run.hpp"
#include "scenarios/run_memory.hpp"
#include "scenarios/variant_stages.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "render/colormap.hpp"
#include "render/image.hpp"
#include "scenarios/colours.hpp"
#include "scenarios/input/scenario.hpp"
#include "sim/deposit.hpp"
#include "tests/read_file.hpp"
#include "tests/scenarios/report_checks.hpp"
#include "tests/scenarios/small_box.hpp"
#include "thermal/mesh.hpp"

namespace beadtwin::scenarios {
namespace {

using testing::read_file;

const std::string kSmall = testing::small_box("small-box", "{voxel_size: 2.5 mm, fields: vtu}") + R"(variants:
  - name: fast
  - name: slow
    set: {sections.walls.speed: 10 mm/s, sections.floor.speed: 10 mm/s, output.skin: stl, output.fields: none}
gates:
  - porosity < 0.5
  - interfaces.too_hot_fraction <= 0.5
)";

// The run's memory adds what each stage declares (the program and the rest the runner's own), and the
// deposit's check before it is made counts the runner's later stages; used alone the deposit counts the same.
TEST(RunMemory, AddsTheStagesCosts) {
  const Scenario sc = load_scenario_text(testing::small_box("costs", "{voxel_size: 2.5 mm}"), "costs.yaml");
  const Variant& v = sc.variants.front();
  const Toolpath tp = variant_toolpath(v);
  const sim::Deposit d = sim::deposit(tp, deposit_options(v));
  const RunMemory need = run_memory(v, tp, d);
  EXPECT_DOUBLE_EQ(need.deposit.bytes(), sim::deposit_cost(d).bytes());
  EXPECT_DOUBLE_EQ(need.thermal.bytes(), thermal::thermal_cost(tp, d, thermal_mesh_options(v)).bytes());
  EXPECT_DOUBLE_EQ(need.surfaces.bytes(), sim::surface_cost(d).bytes());
  const double held = need.program.bytes() + need.deposit.bytes() + need.rest.bytes();
  EXPECT_DOUBLE_EQ(need.side_by_side(), held + need.thermal.bytes() + need.surfaces.bytes());
  EXPECT_DOUBLE_EQ(need.in_turn(), held + std::max(need.thermal.bytes(), need.surfaces.bytes()));
  EXPECT_DOUBLE_EQ(need.least(), need.program.bytes() + need.rest.bytes() + need.thermal.fixed_bytes);
  // Voxels twice as large: the grids an eighth, the surface a quarter.
  const RunMemory coarser = need.at_voxel_ratio(0.5);
  EXPECT_DOUBLE_EQ(coarser.deposit.bytes(), need.deposit.bytes() / 8.0);
  EXPECT_DOUBLE_EQ(coarser.surfaces.bytes(), need.surfaces.bytes() / 4.0);
  EXPECT_DOUBLE_EQ(coarser.least(), need.least());
  EXPECT_EQ(deposit_options(v).later_bytes_per_deposit_byte, later_bytes_per_deposit_byte());
  EXPECT_EQ(sim::DepositOptions{}.later_bytes_per_deposit_byte, later_bytes_per_deposit_byte());
}

// With too little memory to spare for the pictures' surfaces beside the thermal stage (a budget between the
// run's peak estimated side by side and in turn, scenarios::RunMemory) the pictures and the deposit's files
// wait for the thermal stage instead of running beside it: the same figures and the same pictures as with
// room. With room the skin and the pictures share one meshing of the deposit's surface, without it each
// meshes its own: the same skin.
TEST(Run, WithoutRoomBesideTheThermalStageTheSameFiguresAndPictures) {
  const std::string output = "voxel_size: 2.5 mm, skin: ply, fields: vtu";
  const Scenario roomy = load_scenario_text(testing::small_box("tight", "{" + output + "}"), "tight.yaml");
  const Variant& v = roomy.variants.front();
  const Toolpath tp = variant_toolpath(v);
  const RunMemory need = run_memory(v, tp, sim::deposit(tp, deposit_options(v)));
  ASSERT_LT(need.in_turn(), need.side_by_side());
  ASSERT_LT(need.side_by_side(), need.budget);  // the roomy run is side by side
  const Scenario tight = load_scenario_text(
      testing::small_box("tight", fmt::format("{{{}, memory_budget: {:.9g}}}", output,
                                              0.5 * (need.in_turn() + need.side_by_side()) / 1e9)),
      "tight.yaml");
  const auto base = std::filesystem::temp_directory_path();
  std::map<std::string, nlohmann::json> reports;
  for (const auto& [name, sc] :
       {std::pair<std::string, const Scenario*>{"roomy", &roomy}, {"tight", &tight}}) {
    RunOptions o;
    o.out_dir = base / name;
    std::filesystem::remove_all(o.out_dir);
    (void)run_scenario(*sc, o);
    reports[name] = nlohmann::json::parse(read_file(o.out_dir / "report.json"))["variants"][0];
  }
  const nlohmann::json& a = reports["roomy"];
  const nlohmann::json& b = reports["tight"];
  EXPECT_EQ(a["metrics"], b["metrics"]);
  EXPECT_EQ(a["layers"], b["layers"]);
  EXPECT_EQ(a["notes"], b["notes"]);
  ASSERT_EQ(a["images"], b["images"]);
  ASSERT_FALSE(a["images"].empty());
  for (const auto& image : a["images"])
    EXPECT_EQ(read_file(base / "roomy" / image.get<std::string>()),
              read_file(base / "tight" / image.get<std::string>()))
        << image;
  for (const char* file : {"deposit.vdb", "skin.ply", "fields.vtu"})
    EXPECT_TRUE(std::filesystem::exists(base / "tight" / v.name / file)) << file;
  EXPECT_EQ(a["files"]["skin"], b["files"]["skin"]);
  EXPECT_EQ(read_file(base / "roomy" / v.name / "skin.ply"), read_file(base / "tight" / v.name / "skin.ply"));
}

// A part that is mostly surface, at fine voxels: what is meshed from its surface outgrows a budget its
// volume fits (the estimate before the deposit passes). Once the deposit shows it (scenarios::RunMemory),
// an automatic voxel size is made coarser, with a note, and the run fits; a voxel size the scenario set is
// an error naming its key and a size that would fit, before any file is written.
TEST(Run, ASurfaceOverTheMemoryBudgetCoarsensAnAutomaticVoxelOrStops) {
  const auto scenario = [](std::string_view output) {
    return fmt::format(R"(name: surface
units: {{length: mm}}
machine: lsam-ph15
material: cf-abs-20
part:
  open_box: {{size: [200, 150, 40], wall: 4, floor: 1}}
output: {}
render: {{width: 160, height: 100}}
sections:
  - {{name: floor, z: [0, 1], layer_height: 1, bead_width: 4, boundary: {{passes: 1}}, fill: {{angle: 45 deg}}}}
  - {{name: walls, z: [1, 40], layer_height: 1, bead_width: 4, boundary: {{passes: 1}}, fill: none}}
)",
                       output);
  };
  const Scenario roomy = load_scenario_text(scenario("{skin: none}"), "surface.yaml");
  const Variant& v = roomy.variants.front();
  const Toolpath tp = variant_toolpath(v);
  const sim::Deposit fine = sim::deposit(tp, deposit_options(v));
  ASSERT_DOUBLE_EQ(fine.voxel_size_mm, 0.5);  // half the layer height
  RunMemory need = run_memory(v, tp, fine);
  need.budget = need.in_turn() - 1e6;
  const double budget = need.budget;
  ASSERT_GT(budget, fine.memory_estimate_bytes);  // the volume fits
  const double fitting = need.fitting_voxel_mm(fine.voxel_size_mm);
  ASSERT_GT(fitting, fine.voxel_size_mm);

  const auto out = std::filesystem::temp_directory_path() / "beadtwin_run_surface";
  std::filesystem::remove_all(out);
  RunOptions o;
  o.out_dir = out;
  const Scenario automatic = load_scenario_text(
      scenario(fmt::format("{{skin: none, memory_budget: {:.9g}}}", budget / 1e9)), "a.yaml");
  (void)run_scenario(automatic, o);
  const nlohmann::json report = nlohmann::json::parse(read_file(out / "report.json"))["variants"][0];
  EXPECT_DOUBLE_EQ(report["metrics"]["deposit"]["voxel_size_mm"].get<double>(), fitting);
  const std::string notes = report["notes"].dump();
  EXPECT_NE(notes.find("voxel size 0.5 mm: once the deposit's surface is meshed"), std::string::npos)
      << notes;
  EXPECT_NE(notes.find(fmt::format("{} mm used instead", fitting)), std::string::npos) << notes;
  const Toolpath same = variant_toolpath(automatic.variants.front());
  sim::DepositOptions coarser = deposit_options(automatic.variants.front());
  coarser.voxel_size_mm = fitting;
  EXPECT_LE(run_memory(automatic.variants.front(), same, sim::deposit(same, coarser)).in_turn(), budget);

  std::filesystem::remove_all(out);
  const Scenario set = load_scenario_text(
      scenario(fmt::format("{{skin: none, voxel_size: 0.5 mm, memory_budget: {:.9g}}}", budget / 1e9)),
      "s.yaml");
  try {
    (void)run_scenario(set, o);
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "output.voxel_size");
    EXPECT_EQ(e.where().line, set.variants.front().output.voxel_size_at.line);
    EXPECT_NE(std::string(e.what()).find(fmt::format("use a voxel size of {} mm or more", fitting)),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(out / "report.json"));
}

// One variant of the small scenario's report.json: its metrics, layers, sections, pictures, defects and
// temperature history, with the files they name in `out`.
void expect_small_variant(const nlohmann::json& v, const std::filesystem::path& out) {
  const auto& m = v["metrics"];
  for (const char* key :
       {"layers", "print_time_s", "print_length_mm", "travel_length_mm", "commanded_volume_mm3",
        "deposited_volume_mm3", "mass_kg", "porosity", "min_stock_mm", "undercut_fraction"})
    EXPECT_TRUE(m.contains(key)) << key;
  for (const char* key : {"count", "too_hot_fraction", "too_cold_fraction", "min_healing", "mean_healing"})
    EXPECT_TRUE(m["interfaces"].contains(key)) << key;
  for (const char* key : {"min", "mean", "max"}) EXPECT_TRUE(m["layer_time_s"].contains(key)) << key;
  EXPECT_EQ(m["layers"], 6);
  // Interfaces: every contact where a bead landed on or against an older one; the layers' counts add up.
  int per_layer = 0;
  for (const auto& l : v["layers"]) per_layer += l["interfaces"].get<int>();
  EXPECT_GT(m["interfaces"]["count"].get<int>(), 5);
  EXPECT_EQ(m["interfaces"]["count"].get<int>(), per_layer);
  // And so do the sections'.
  ASSERT_EQ(v["sections"].size(), 2u);
  EXPECT_EQ(v["sections"][0]["name"], "floor");
  EXPECT_EQ(v["sections"][0]["interfaces"].get<int>() + v["sections"][1]["interfaces"].get<int>(), per_layer);
  // Conservation: every commanded mm³ is in the voxel model.
  EXPECT_NEAR(m["deposited_volume_mm3"].get<double>() / m["commanded_volume_mm3"].get<double>(), 1.0, 0.02);
  ASSERT_EQ(v["layers"].size(), 6u);
  for (const char* key : {"index", "z_mm", "section", "start_s", "duration_s", "substrate_temp_c",
                          "healing_min", "too_hot", "too_cold"})
    EXPECT_TRUE(v["layers"][0].contains(key)) << key;
  EXPECT_EQ(v["layers"][0]["section"], "floor");
  EXPECT_EQ(v["layers"][5]["section"], "walls");
  EXPECT_EQ(v["gates"].size(), 2u);
  // The default pictures: isometric and top views by fusion verdict, isometric by section, by substrate
  // temperature and by stock against the CAD.
  ASSERT_EQ(v["images"].size(), 5u);
  for (const auto& img : v["images"])
    EXPECT_GT(std::filesystem::file_size(out / img.get<std::string>()), 1000u);
  EXPECT_GT(std::filesystem::file_size(out / v["program"].get<std::string>()), 1000u);
  EXPECT_TRUE(std::filesystem::exists(out / v["deposit"].get<std::string>()));
  // The deposit's defects: counted in the metrics, listed with where they are. The box's square corners
  // are tighter than the LSAM roller (1.5 in wide) follows, and no pull-back lifts it there.
  for (const char* key : {"voids", "void_volume_mm3", "plough_volume_mm3", "unsupported_length_mm",
                          "roller_corners", "collisions"})
    EXPECT_TRUE(m["defects"].contains(key)) << key;
  EXPECT_GE(m["defects"]["roller_corners"].get<int>(), 4 * 6);
  ASSERT_FALSE(v["defects"].empty());
  for (const char* key : {"kind", "position_mm", "layer", "move", "source_line", "size", "detail"})
    EXPECT_TRUE(v["defects"][0].contains(key)) << key;
  for (const char* key : {"fill_ratio", "bead_height_mm", "void_mm3", "plough_mm3", "unsupported_mm"})
    EXPECT_TRUE(v["layers"][0].contains(key)) << key;
  EXPECT_NEAR(v["layers"][0]["bead_height_mm"].get<double>(), 5.0, 0.5);
  // The temperature history of the default layers (0, 14, 29) the print reaches: six layers, only layer 0.
  const auto& history = v["temperature_history"];
  ASSERT_EQ(history["layers"].size(), 1u);
  EXPECT_EQ(history["layers"][0]["index"], 0);
  ASSERT_GT(history["times_s"].size(), 10u);
  EXPECT_EQ(history["layers"][0]["temp_c"].size(), history["times_s"].size());
  EXPECT_LE(history["layers"][0]["temp_c"][0].get<double>(), 200.0 + 1e-6);
  const double interval = history["times_s"][1].get<double>() - history["times_s"][0].get<double>();
  EXPECT_NEAR(interval, 5.0, 0.011);  // thermal.sample_interval, rounded to 0.01 s
}

// The small scenario's files for other programs, as report.json, report.html and the stages list them.
void expect_small_files(const nlohmann::json& j, const RunResult& r, const std::filesystem::path& out) {
  // Files for other programs: by default the skin as PLY, and here the fields as .vtu, beside deposit.vdb;
  // the slow variant asks for an STL skin and no fields.
  const auto& fast_files = j["variants"][0]["files"];
  EXPECT_EQ(fast_files["deposit"]["path"], "fast/deposit.vdb");
  EXPECT_EQ(fast_files["deposit"]["bytes"].get<std::uintmax_t>(),
            std::filesystem::file_size(out / "fast/deposit.vdb"));
  EXPECT_EQ(fast_files["skin"]["path"], "fast/skin.ply");
  EXPECT_EQ(fast_files["skin"]["bytes"].get<std::uintmax_t>(),
            std::filesystem::file_size(out / "fast/skin.ply"));
  EXPECT_GT(fast_files["skin"]["triangles"].get<std::size_t>(), 1000u);
  const nlohmann::json& beads = fast_files["skin"]["bead_by_bead_stl"];
  EXPECT_EQ(beads["bytes"].get<std::uintmax_t>(), 84u + 50u * beads["triangles"].get<std::uintmax_t>());
  EXPECT_NEAR(fast_files["skin"]["bead_by_bead_triangles_over_skin"].get<double>(),
              beads["triangles"].get<double>() / fast_files["skin"]["triangles"].get<double>(), 1e-9);
  EXPECT_EQ(fast_files["fields"]["path"], "fast/fields.vtu");
  EXPECT_EQ(fast_files["fields"]["bytes"].get<std::uintmax_t>(),
            std::filesystem::file_size(out / "fast/fields.vtu"));
  EXPECT_EQ(fast_files["fields"]["cells"], j["variants"][0]["metrics"]["deposit"]["voxels"]);
  EXPECT_EQ(read_file(out / "fast/skin.ply").rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
  EXPECT_NE(read_file(out / "fast/fields.vtu").find("<VTKFile type=\"UnstructuredGrid\""), std::string::npos);
  const auto& slow_files = j["variants"][1]["files"];
  EXPECT_EQ(slow_files["skin"]["path"], "slow/skin.stl");
  EXPECT_TRUE(std::filesystem::exists(out / "slow/skin.stl"));
  EXPECT_TRUE(slow_files["fields"].is_null());
  EXPECT_FALSE(std::filesystem::exists(out / "slow/fields.vtu"));
  const std::string html = read_file(out / "report.html");
  EXPECT_NE(html.find("<a href=\"fast/skin.ply\">fast/skin.ply</a>"), std::string::npos);
  EXPECT_NE(html.find("<a href=\"fast/fields.vtu\">fast/fields.vtu</a>"), std::string::npos);
  EXPECT_NE(html.find("times the skin's"), std::string::npos);
  for (const auto& v : r.variants) {
    bool skin_stage = false;
    for (const auto& t : v.stage_times) skin_stage = skin_stage || t.name == "skin";
    EXPECT_TRUE(skin_stage) << v.name;
  }
}

TEST(Run, SmallScenarioEndToEnd) {
  const Scenario sc = load_scenario_text(kSmall, "small.yaml");
  const auto out = std::filesystem::temp_directory_path() / "beadtwin_run_test";
  std::filesystem::remove_all(out);
  RunOptions o;
  o.out_dir = out;
  const RunResult r = run_scenario(sc, o);
  ASSERT_EQ(r.variants.size(), 2u);

  const auto j = nlohmann::json::parse(read_file(out / "report.json"));
  EXPECT_EQ(j["tool"], "beadtwin");
  EXPECT_EQ(j["scenario"], "small-box");
  EXPECT_EQ(j["passed"].get<bool>(), r.passed);
  ASSERT_EQ(j["variants"].size(), 2u);
  for (const auto& v : j["variants"]) expect_small_variant(v, out);
  expect_small_files(j, r, out);

  // The part against its CAD: measured (a sliced part has one). The open box's walls are two passes of
  // 20 mm beads laid with their outer edges on the 40 mm wall's faces and no stock: at every layer's top and
  // bottom the bead's round side (radius h/2 = 2.5 mm) leaves a groove whose floor is h/2 inside the face,
  // so the sides are short of the CAD between the beads' widest points (undercut), by up to
  // (sqrt(2) - 1) h/2 = 1.04 mm straight out from a groove.
  for (const auto& v : j["variants"]) {
    const auto& m = v["metrics"];
    ASSERT_TRUE(m["min_stock_mm"].is_number()) << m.dump();
    ASSERT_TRUE(m["undercut_fraction"].is_number());
    EXPECT_LT(m["min_stock_mm"].get<double>(), 0.0);
    EXPECT_GT(m["undercut_fraction"].get<double>(), 0.0);
    EXPECT_LT(m["undercut_fraction"].get<double>(), 1.0);
    for (const char* key : {"max_stock_mm", "mean_stock_mm", "below_requested_stock_fraction",
                            "deviation_rms_mm", "machining_waste_fraction"})
      EXPECT_TRUE(m[key].is_number()) << key;
    EXPECT_TRUE(m["cad"]["deviation_map"]["white_at_mm"].is_number());
  }
  EXPECT_NE(read_file(out / "report.html").find("<img src=\"fast/deviation.png\""), std::string::npos);
  // Without the bands (thermal.uncertainty off) the notes say that the verdicts rest on the files' values,
  // which of those have ranges, and how to get the bands.
  for (const auto& v : j["variants"]) {
    const auto& notes = v["notes"];
    const auto it = std::find_if(notes.begin(), notes.end(), [](const nlohmann::json& n) {
      return n.get<std::string>().find("inputs that decide them have plausible ranges") != std::string::npos;
    });
    ASSERT_NE(it, notes.end()) << notes.dump();
    const std::string note = it->get<std::string>();
    for (const char* key : {"fusion.reptation_time", "fusion.wlf_c1", "environment.convection",
                            "thermal.uncertainty: linearised"})
      EXPECT_NE(note.find(key), std::string::npos) << key << " not in: " << note;
  }
  // The slow variant prints the same part with longer layer times, so its substrate is colder.
  const auto& fast = j["variants"][0];
  const auto& slow = j["variants"][1];
  EXPECT_GT(slow["metrics"]["layer_time_s"]["mean"].get<double>(),
            3 * fast["metrics"]["layer_time_s"]["mean"].get<double>());
  EXPECT_LT(slow["layers"][5]["substrate_temp_c"]["mean"].get<double>(),
            fast["layers"][5]["substrate_temp_c"]["mean"].get<double>());

  const std::string junit = read_file(out / "junit.xml");
  EXPECT_NE(junit.find("<testsuites"), std::string::npos);
  EXPECT_NE(junit.find("testcase classname=\"small-box.fast\" name=\"porosity &lt; 0.5\""), std::string::npos)
      << junit;
  EXPECT_NE(read_file(out / "report.html").find("<img src=\"fast/fusion.png\""), std::string::npos);
  EXPECT_NE(read_file(out / "summary.md").find("| fast (baseline) |"), std::string::npos);
  // Nothing half-written is left behind.
  for (const auto& e : std::filesystem::recursive_directory_iterator(out))
    EXPECT_EQ(e.path().filename().string().rfind(".tmp-", 0), std::string::npos) << e.path();
}

// The built-in scenario, as `beadtwin run` runs it (smaller pictures): its open box is measured against its
// CAD. It asks for no stock: every boundary pass lays its bead's edge on the CAD's faces, so the sides are
// short of the CAD except at each bead's widest. At its voxels (s = h/2 = 2.54 mm) the grid sees each layer
// through two rows of voxel centres, both h/4 from the layer's mid-height, where the bead reaches
// (w − h)/2 + sqrt((h/2)² − (h/4)²) = w/2 − 0.34 mm: the sides come out evenly 0.34 mm short (the scallops
// themselves, up to (√2 − 1) h/2 = 1.05 mm deep, are finer than the voxels). The sides are most of the
// surface measured; the bottom stands on the table and is left out.
TEST(Run, DefaultScenarioMeasuresThePartAgainstItsCad) {
  Scenario sc = load_default_scenario();
  for (Variant& v : sc.variants) {
    v.render.width = 160;
    v.render.height = 100;
  }
  RunOptions o;
  o.out_dir = std::filesystem::temp_directory_path() / "beadtwin_run_default";
  std::filesystem::remove_all(o.out_dir);
  const RunResult r = run_scenario(sc, o);
  const auto j = nlohmann::json::parse(read_file(o.out_dir / "report.json"));
  ASSERT_EQ(j["variants"].size(), 2u);
  // What the default shows: the cautious baseline's layers come too late to heal and it fails the too-cold
  // gate; the faster layers its window points to carry and heal, and pass every gate.
  ASSERT_EQ(r.variants.size(), 2u);
  EXPECT_FALSE(r.variants[0].passed);
  EXPECT_GT(r.variants[0].metrics.too_cold_fraction, 0.3);
  EXPECT_LT(r.variants[0].metrics.too_hot_fraction, 0.05);
  EXPECT_TRUE(r.variants[1].passed);
  EXPECT_LT(r.variants[1].metrics.too_cold_fraction, 0.1);
  const auto& m = j["variants"][0]["metrics"];
  ASSERT_TRUE(m["min_stock_mm"].is_number()) << m.dump();
  ASSERT_TRUE(m["undercut_fraction"].is_number());
  // Least stock at the box's four outer vertical edges: sharp in the CAD, while a bead turns round its pass's
  // corner (w/2 in from each face) on a circle of radius w/2, so the corner falls short by √2 w/2 − w/2 =
  // 4.37 mm at a bead's widest and by hypot(√2 w/2 − (w − h)/2, h/2) − h/2 = 4.81 mm level with a groove.
  const double w = 0.83 * 25.4, lh = 0.2 * 25.4;
  const double widest = (std::sqrt(2.0) - 1) * w / 2;
  const double groove = std::hypot(std::sqrt(2.0) * w / 2 - (w - lh) / 2, lh / 2) - lh / 2;
  // The least of all is at the box's top corners (the least stock is sought to within a hundredth of a voxel,
  // and found at a CAD corner, where no sample's cell centre falls): the geometry gives the same 4.81 mm
  // there, the top of the last layer level with the CAD's top, but the voxels' iso-surface rounds the
  // print's top edge into its rounded corner (at a corner of three voxel faces it lies s/√3 inside; here,
  // a corner already rounded, less): allow a quarter of a voxel more.
  const double s = sc.variants[0].output.voxel_size_mm;  // 0.1 in
  ASSERT_GT(s, 0.0);
  EXPECT_GE(m["min_stock_mm"].get<double>(), -groove - 0.25 * s);
  EXPECT_LE(m["min_stock_mm"].get<double>(), -widest + 0.1);
  // The open box: 24 x 18 x 10 in outside, walls 4.7725 in, floor 2 in.
  constexpr double kIn = 25.4;
  const double lx = 24 * kIn, ly = 18 * kIn, h = 10 * kIn, wall = 4.7725 * kIn, floor = 2 * kIn;
  const double sides = 2 * (lx + ly) * h + 2 * (lx + ly - 4 * wall) * (h - floor);
  const double tops = lx * ly;  // wall tops and the floor's top, seen from above
  EXPECT_NEAR(m["cad"]["cad_area_mm2"].get<double>(), sides + tops, 1e-6 * (sides + tops));
  EXPECT_GT(m["undercut_fraction"].get<double>(), 0.9 * sides / (sides + tops));
  // Most of the surface is sides, so the median stock is theirs.
  const double side_short =
      (w - lh) / 2 + std::sqrt(std::pow(lh / 2, 2) - std::pow(lh / 4, 2)) - w / 2;  // -0.34
  EXPECT_NEAR(m["cad"]["stock_percentiles_mm"]["p50"].get<double>(), side_short, 0.1);
  EXPECT_LT(m["undercut_fraction"].get<double>(), 1.0);
  EXPECT_EQ(m["cad"]["requested_stock_mm"].get<double>(), 0.0);
  EXPECT_EQ(m["cad"]["deviation_map"]["white_at_mm"].get<double>(), 0.0);
  EXPECT_NEAR(m["cad"]["deviation_map"]["red_at_mm"].get<double>(), 0.2 * kIn, 1e-9);  // a layer height
  const auto& images = j["variants"][0]["images"];
  ASSERT_EQ(images.size(), 5u);
  EXPECT_EQ(images[4], "baseline/deviation.png");
  EXPECT_GT(std::filesystem::file_size(o.out_dir / images[4].get<std::string>()), 1000u);
  const std::string html = read_file(o.out_dir / "report.html");
  EXPECT_NE(html.find("The part against its CAD"), std::string::npos);
  // Its legend shows the picture's colours: the diverging map's ends and middle.
  for (const double t : {0.0, 0.5, 1.0})
    EXPECT_NE(html.find(fmt::format("background:{}", hex(render::ColourMap::diverging().at(t)))),
              std::string::npos)
        << t;
  EXPECT_NE(html.find("<img src=\"baseline/deviation.png\""), std::string::npos);
}

// The render block: pictures of each variant with their own cameras, colourings, cutaway, earlier stage
// and EXR, progress frames, and the variants' comparison sheets.
TEST(Run, PicturesOfTheRenderBlock) {
  std::string text = kSmall;
  const std::string render = R"(render:
  width: 160
  height: 100
  samples: 2
  exr: true
  images:
    - {colour: fusion}
    - {name: inside, colour: temperature, time: 5 min, view: front, cut: {point: [120, 90, 0], normal: [0, -1, 0]}}
    - {colour: layer, layer: 2, view: top}
  progress: {colour: layer, every: 2}
)";
  text.replace(text.find("render: {width: 160, height: 100}\n"),
               std::string("render: {width: 160, height: 100}\n").size(), render);
  const Scenario sc = load_scenario_text(text, "pictures.yaml");
  RunOptions o;
  o.out_dir = std::filesystem::temp_directory_path() / "beadtwin_run_pictures";
  std::filesystem::remove_all(o.out_dir);
  run_scenario(sc, o);
  const auto j = nlohmann::json::parse(read_file(o.out_dir / "report.json"));
  for (const auto& v : j["variants"]) {
    const std::string name = v["name"];
    EXPECT_EQ(v["images"],
              nlohmann::json({name + "/fusion.png", name + "/inside.png", name + "/layer-top.png"}));
    ASSERT_EQ(v["images_exr"].size(), 3u);
    for (const auto& f : v["images_exr"])
      EXPECT_GT(std::filesystem::file_size(o.out_dir / f.get<std::string>()), 1000u);
    // Six layers, every second one: after layers 1, 3 and 5.
    ASSERT_EQ(v["progress_frames"].size(), 3u);
    EXPECT_EQ(v["progress_frames"][0], name + "/progress/frame-0000.png");
    for (const auto& f : v["progress_frames"])
      EXPECT_TRUE(std::filesystem::exists(o.out_dir / f.get<std::string>()));
  }
  // One sheet per picture, the two variants side by side: twice as wide as a picture.
  EXPECT_EQ(j["sheets"],
            nlohmann::json({"comparison-fusion.png", "comparison-inside.png", "comparison-layer-top.png"}));
  const render::Image sheet = render::read_image(o.out_dir / "comparison-fusion.png");
  EXPECT_EQ(sheet.width, 320);
  // The variants print differently: their fusion pictures differ; the part after layer 2 is not the
  // whole part.
  EXPECT_NE(render::read_image(o.out_dir / "fast" / "fusion.png"),
            render::read_image(o.out_dir / "slow" / "fusion.png"));
  EXPECT_NE(render::read_image(o.out_dir / "fast" / "progress" / "frame-0000.png"),
            render::read_image(o.out_dir / "fast" / "progress" / "frame-0002.png"));
  const std::string html = read_file(o.out_dir / "report.html");
  EXPECT_NE(html.find("comparison-inside.png"), std::string::npos);
  // The variants table marks the slow variant's longer print against the baseline (the first variant).
  EXPECT_NE(html.find("fast <span class=muted>(baseline)</span>"), std::string::npos);
  EXPECT_NE(html.find("<td class=worse>"), std::string::npos);
}

// A gate relative to the baseline (here the first variant, "fast"): the slow variant takes far longer to
// print and fails it; the fast one passes against itself. The report keeps the threshold it was judged by.
TEST(Run, RelativeGateFailsTheSlowerVariant) {
  std::string text = kSmall;
  text.replace(text.find("  - porosity < 0.5\n"), std::string("  - porosity < 0.5\n").size(),
               "  - porosity < 0.5\n  - print_time_s <= baseline * 1.05\n");
  const Scenario sc = load_scenario_text(text, "relative.yaml");
  RunOptions o;
  // Progress reports: every stage starts at 0, and the long ones report their way up to 1, in order.
  std::map<std::string, std::vector<double>> reports;
  o.progress = [&](const std::string& variant, const std::string& stage, double fraction) {
    reports[variant + "/" + stage].push_back(fraction);
  };
  o.out_dir = std::filesystem::temp_directory_path() / "beadtwin_run_relative";
  std::filesystem::remove_all(o.out_dir);
  const RunResult r = run_scenario(sc, o);
  ASSERT_EQ(r.variants.size(), 2u);
  ASSERT_EQ(r.variants[0].gates.size(), 3u);
  EXPECT_EQ(r.variants[0].gates[1].expr, "print_time_s <= baseline * 1.05");
  EXPECT_TRUE(r.variants[0].gates[1].passed);
  EXPECT_FALSE(r.variants[1].gates[1].passed) << r.variants[1].gates[1].message;
  EXPECT_FALSE(r.variants[1].passed);
  EXPECT_FALSE(r.passed);
  const auto j = nlohmann::json::parse(read_file(o.out_dir / "report.json"));
  EXPECT_DOUBLE_EQ(j["variants"][1]["gates"][1]["threshold"].get<double>(),
                   1.05 * j["variants"][0]["metrics"]["print_time_s"].get<double>());
  for (const char* stage : {"fast/deposit", "fast/thermal", "slow/deposit", "slow/thermal", "fast/render"}) {
    SCOPED_TRACE(stage);
    const std::vector<double>& f = reports[stage];
    ASSERT_FALSE(f.empty());
    EXPECT_EQ(f.front(), 0.0);
    EXPECT_TRUE(std::is_sorted(f.begin(), f.end()));
    EXPECT_LE(f.back(), 1.0);
  }
  EXPECT_GT(reports["fast/thermal"].size(), 5u);
  EXPECT_DOUBLE_EQ(reports["fast/thermal"].back(), 1.0);
  EXPECT_DOUBLE_EQ(reports["fast/deposit"].back(), 1.0);

  // Per section: what it took to print adds up to the part's (travel between sections aside), and the
  // report keeps each section's row.
  for (const auto& v : r.variants) {
    SCOPED_TRACE(v.name);
    ASSERT_EQ(v.metrics.sections.size(), 2u);
    double mass = 0, time = 0, length = 0;
    int layers = 0;
    for (const SectionRow& s : v.metrics.sections) {
      mass += s.mass_kg, time += s.print_time_s, length += s.print_length_mm, layers += s.layers;
      EXPECT_GT(s.mean_layer_time_s, 0.0) << s.name;
    }
    EXPECT_EQ(layers, v.metrics.layers);
    EXPECT_NEAR(mass, v.metrics.mass_kg, 0.01 * v.metrics.mass_kg);
    EXPECT_NEAR(length, v.metrics.print_length_mm, 1e-6 * v.metrics.print_length_mm);
    EXPECT_LE(time, v.metrics.print_time_s + 1e-6);
    EXPECT_GT(time, 0.9 * v.metrics.print_time_s);
  }
  EXPECT_EQ(j["variants"][1]["sections"][1]["name"], "walls");
  EXPECT_DOUBLE_EQ(j["variants"][1]["sections"][1]["mass_kg"].get<double>(),
                   r.variants[1].metrics.sections[1].mass_kg);

  // junit.xml as CI systems read it: valid JUnit XML, one test case per gate and variant, the counts adding
  // up, and the failed gate with its message.
  const testing::XmlDoc junit = testing::read_junit(o.out_dir / "junit.xml");
  ASSERT_TRUE(junit);
  const auto number = [&](const std::string& xpath) { return testing::xpath_number(junit.get(), xpath); };
  int failed = 0;
  for (const auto& v : r.variants)
    for (const auto& g : v.gates) failed += g.passed ? 0 : 1;
  EXPECT_EQ(number("count(/testsuites/testsuite)"), 2);
  EXPECT_EQ(number("count(//testcase)"), 6);
  EXPECT_EQ(number("/testsuites/@tests"), 6);
  EXPECT_EQ(number("count(//failure)"), failed);
  EXPECT_EQ(number("/testsuites/@failures"), failed);
  EXPECT_EQ(number("sum(/testsuites/testsuite/@failures)"), failed);
  EXPECT_EQ(number("count(//testsuite[@name='small-box.slow']/testcase)"), 3);
  EXPECT_EQ(
      testing::xpath_string(junit.get(),
                            "//testsuite[@name='small-box.slow']/testcase[@name='print_time_s <= baseline * "
                            "1.05']/failure/@message"),
      r.variants[1].gates[1].message);
  EXPECT_EQ(number("count(//testsuite[@name='small-box.fast']/testcase[@name='print_time_s <= baseline * "
                   "1.05']/failure)"),
            0);

  // report.html's plots carry each variant's layers as report.json has them: the substrate temperature and
  // the layer time with its window, for the page's script (Chart.js, embedded once) to draw.
  const std::string html = read_file(o.out_dir / "report.html");
  EXPECT_EQ(html.find("Chart.js v3"), html.rfind("Chart.js v3"));
  EXPECT_NE(html.find("Chart.js v3"), std::string::npos);
  std::map<std::string, std::vector<nlohmann::json>> plots;  // by kind, in variant order
  for (const nlohmann::json& p : testing::report_plots(html)) plots[p["kind"]].push_back(p);
  ASSERT_EQ(plots["substrate"].size(), 2u);
  ASSERT_EQ(plots["layer_time"].size(), 2u);
  ASSERT_EQ(plots["history"].size(), 2u);  // the default history layers
  for (std::size_t k = 0; k < 2; ++k) {
    SCOPED_TRACE(k);
    const auto& layers = j["variants"][k]["layers"];
    const auto& substrate = plots["substrate"][k];
    const auto& times = plots["layer_time"][k];
    ASSERT_EQ(substrate["layers"].size(), layers.size());
    ASSERT_EQ(times["duration"].size(), layers.size());
    ASSERT_EQ(substrate["support"].size(), layers.size());
    for (std::size_t i = 0; i < layers.size(); ++i) {
      EXPECT_EQ(substrate["layers"][i], layers[i]["index"]);
      EXPECT_EQ(substrate["support"][i], layers[i]["support_limit_c"]["mean"]);
      EXPECT_EQ(substrate["mean"][i], layers[i]["substrate_temp_c"]["mean"]);
      EXPECT_EQ(substrate["verdicts"][i], layers[i]["verdict"]);
      EXPECT_DOUBLE_EQ(times["duration"][i].get<double>(), layers[i]["duration_s"].get<double>());
      // The window's band starts at its least (0 where nothing bounds it below) and ends at its most.
      const auto& window = layers[i]["layer_time_window_s"];
      const auto& band = times["window"][i];
      if (band.is_null()) continue;
      EXPECT_EQ(band[0].get<double>(), window["min"].is_null() ? 0.0 : window["min"].get<double>());
      EXPECT_EQ(band[1], window["max"]);
    }
  }
}

// The shipped desktop scenario: PrusaSlicer's program for a small PLA box, simulated as written, with its
// pictures (a cutaway among them) at a small size.
TEST(Run, ShippedDesktopScenarioFromPrusaSlicer) {
  const Scenario sc =
      load_scenario(std::filesystem::path(BEADTWIN_SOURCE_DIR) / "scenarios" / "data" / "desktop-prusa.yaml",
                    {parse_setting("render.width=320"), parse_setting("render.height=200")});
  RunOptions o;
  o.out_dir = std::filesystem::temp_directory_path() / "beadtwin_run_desktop";
  std::filesystem::remove_all(o.out_dir);
  const RunResult r = run_scenario(sc, o);
  ASSERT_EQ(r.variants.size(), 1u);
  const Metrics& m = r.variants[0].metrics;
  EXPECT_EQ(m.layers, 8);  // 0.3 mm first layer, then 0.3 mm to 2.4 mm
  EXPECT_GT(m.interfaces, 1000);
  EXPECT_NEAR(m.deposited_volume_mm3 / m.commanded_volume_mm3, 1.0, 0.01);
  ASSERT_EQ(r.variants[0].images.size(), 3u);
  for (const std::string& image : r.variants[0].images)
    EXPECT_GT(std::filesystem::file_size(o.out_dir / image), 1000u);
}

// The shipped scenarios not run by a test of their own run as shipped, with small pictures: every variant
// reports, with its pictures, and the report parses.
void expect_shipped_scenario_runs(const std::string& file) {
  const Scenario sc = load_scenario(std::filesystem::path(BEADTWIN_SOURCE_DIR) / "scenarios" / "data" / file,
                                    {parse_setting("render.width=160"), parse_setting("render.height=100")});
  RunOptions o;
  o.out_dir = std::filesystem::temp_directory_path() / ("beadtwin_shipped_" + sc.name);
  std::filesystem::remove_all(o.out_dir);
  const RunResult r = run_scenario(sc, o);
  ASSERT_EQ(r.variants.size(), sc.variants.size());
  const auto j = nlohmann::json::parse(read_file(o.out_dir / "report.json"));
  ASSERT_EQ(j["variants"].size(), sc.variants.size());
  for (const auto& v : j["variants"]) {
    EXPECT_GT(v["metrics"]["layers"].get<int>(), 0) << v["name"];
    EXPECT_FALSE(v["images"].empty()) << v["name"];
    for (const auto& image : v["images"])
      EXPECT_TRUE(std::filesystem::exists(o.out_dir / image.get<std::string>())) << image;
  }
  EXPECT_TRUE(std::filesystem::exists(o.out_dir / "report.html"));
  EXPECT_TRUE(std::filesystem::exists(o.out_dir / "junit.xml"));
}

TEST(Run, ShippedFig7ScenarioRuns) {
  expect_shipped_scenario_runs("fig7-three-sections.yaml");
}
TEST(Run, ShippedFillStylesScenarioRuns) {
  expect_shipped_scenario_runs("fill-styles.yaml");
}

TEST(Run, UnknownVariantIsAnInputError) {
  const Scenario sc = load_scenario_text(kSmall, "small.yaml");
  RunOptions o;
  o.out_dir = std::filesystem::temp_directory_path() / "beadtwin_run_test_bad";
  o.variants = {"nope"};
  EXPECT_THROW((void)run_scenario(sc, o), InputError);
  EXPECT_THROW((void)slice_program(sc, "nope"), InputError);
  EXPECT_NE(slice_program(sc, "slow").find("(LAYER 0 SECTION floor"), std::string::npos);
}

// A single open bead has no interface: its healing is not measured (null in report.json, a dash in the
// summary), and a gate on it fails with a message saying so rather than passing on a made-up 0.
TEST(Run, SingleLayerHasNoHealingToReport) {
  const std::string text = R"(name: one-layer
units: {length: mm}
machine: lsam-ph15
material: cf-abs-20
output: {voxel_size: 2.5 mm, fields: vtu}
render: {width: 160, height: 100}
sections:
  - {name: bead, layers: 1, layer_height: 5, bead_width: 20, outline: {points: [[0, 0], [200, 0], [200, 100]], closed: false}}
gates:
  - interfaces.min_healing >= 0.5
)";
  const Scenario sc = load_scenario_text(text, "one.yaml");
  RunOptions o;
  o.out_dir = std::filesystem::temp_directory_path() / "beadtwin_run_one_layer";
  std::filesystem::remove_all(o.out_dir);
  const RunResult r = run_scenario(sc, o);
  ASSERT_EQ(r.variants.size(), 1u);
  EXPECT_FALSE(r.passed);
  ASSERT_EQ(r.variants[0].gates.size(), 1u);
  EXPECT_NE(r.variants[0].gates[0].message.find("not measured"), std::string::npos)
      << r.variants[0].gates[0].message;
  const auto j = nlohmann::json::parse(read_file(o.out_dir / "report.json"));
  EXPECT_TRUE(j["variants"][0]["metrics"]["interfaces"]["min_healing"].is_null());
  // An AM Outline prints a path, not a part: there is no CAD to measure against, and no deviation map.
  EXPECT_TRUE(j["variants"][0]["metrics"]["min_stock_mm"].is_null());
  EXPECT_TRUE(j["variants"][0]["metrics"]["undercut_fraction"].is_null());
  EXPECT_TRUE(j["variants"][0]["metrics"]["cad"].is_null());
  EXPECT_EQ(j["variants"][0]["images"].size(), 4u);
  EXPECT_NE(read_file(o.out_dir / "summary.md").find("| —"), std::string::npos);
}

}  // namespace
}  // namespace beadtwin::scenarios
