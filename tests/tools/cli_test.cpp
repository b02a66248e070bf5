// The beadtwin program as a user runs it: exit codes and messages (README, command line).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/read_file.hpp"
#include "tests/scenarios/small_box.hpp"
#include "tests/shell.hpp"

namespace {

using beadtwin::testing::read_file;

using Result = beadtwin::testing::ShellResult;

// The beadtwin program with `args`, its stdout and stderr together.
Result run(const std::string& args) {
  return beadtwin::testing::shell(std::string(BEADTWIN_BINARY) + " " + args + " 2>&1");
}

std::filesystem::path write(const std::string& name, const std::string& text) {
  const auto p = std::filesystem::temp_directory_path() / name;
  std::ofstream(p) << text;
  return p;
}

TEST(Cli, HelpDocumentsTheCommands) {
  const Result top = run("--help");
  EXPECT_EQ(top.code, 0);
  EXPECT_NE(top.output.find("run"), std::string::npos);
  EXPECT_NE(top.output.find("Exit codes"), std::string::npos);
  const Result sub = run("run --help");
  EXPECT_EQ(sub.code, 0);
  EXPECT_NE(sub.output.find("--variant"), std::string::npos);
  EXPECT_NE(sub.output.find("--out"), std::string::npos);
}

TEST(Cli, TheProgramLoadsOpenImageIOOnlyToWritePictures) {
  // OpenImageIO brings 260 shared libraries, bound at every start when linked (render/image_codec.hpp);
  // it lives in a module that the program loads when it writes an image.
  const Result libraries = beadtwin::testing::shell(std::string("ldd ") + BEADTWIN_BINARY + " 2>&1");
  ASSERT_EQ(libraries.code, 0) << libraries.output;
  EXPECT_NE(libraries.output.find("libopenvdb"), std::string::npos) << libraries.output;
  EXPECT_EQ(libraries.output.find("libOpenImageIO"), std::string::npos) << libraries.output;
}

TEST(Cli, UsageErrorsExitWithTwo) {
  EXPECT_EQ(run("").code, 2);
  EXPECT_EQ(run("frobnicate").code, 2);
  EXPECT_EQ(run("run --no-such-option").code, 2);
}

TEST(Cli, UnknownScenarioKeyExitsWithTwoAndNamesTheLine) {
  const auto p =
      write("bt_cli_unknown.yaml",
            "name: x\nmachine: lsam-ph15\nmaterial: cf-abs-20\npart:\n  box: {size: [100, 100, 10]}\n"
            "sections:\n  - {name: a, z: [0, 10], boundary: {passes: 1}}\nsurprise: 1\n");
  const auto out = std::filesystem::temp_directory_path() / "bt_cli_unknown_out";
  std::filesystem::remove_all(out);
  const Result r = run("run " + p.string() + " -o " + out.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find(p.string() + ":8:1: surprise: unknown key"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out / "report.json")) << "no report for bad input";
}

TEST(Cli, MissingScenarioFileExitsWithTwo) {
  const Result r = run("run /nonexistent/scenario.yaml -o /tmp/bt_cli_missing");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("no such scenario file"), std::string::npos) << r.output;
}

TEST(Cli, RunPrintsTheReportAndGatesSetTheExitCode) {
  const std::string base =
      "name: tiny\nunits: {length: mm}\nmachine: lsam-ph15\nmaterial: cf-abs-20\n"
      "part:\n  box: {size: [120, 80, 15]}\n"
      "output: {voxel_size: 2.5 mm}\n"
      "render: {width: 120, height: 80}\n"
      "sections:\n  - {name: a, z: [0, 15], layer_height: 5, bead_width: 20, boundary: {passes: 1}, fill: "
      "{angle: 0 deg}}\n";
  const auto out = std::filesystem::temp_directory_path() / "bt_cli_run";
  std::filesystem::remove_all(out);
  const Result pass = run("run " + write("bt_cli_pass.yaml", base + "gates:\n  - layers == 3\n").string() +
                          " -q -o " + out.string());
  EXPECT_EQ(pass.code, 0) << pass.output;
  EXPECT_NE(pass.output.find("report: " + (out / "report.html").string()), std::string::npos) << pass.output;
  EXPECT_TRUE(std::filesystem::exists(out / "report.json"));
  const Result fail = run("run " + write("bt_cli_fail.yaml", base + "gates:\n  - layers > 3\n").string() +
                          " -q -o " + out.string());
  EXPECT_EQ(fail.code, 1) << fail.output;
  EXPECT_NE(fail.output.find("FAILED"), std::string::npos);
  // --set on the command line changes the run: four layers of 15/4 mm make the passing gate fail, and
  // the report keeps the setting among the variant's parameters.
  const Result set = run("run " + (std::filesystem::temp_directory_path() / "bt_cli_pass.yaml").string() +
                         " --set sections.a.layer_height=3.75mm -q -o " + out.string());
  EXPECT_EQ(set.code, 1) << set.output;
  EXPECT_NE(read_file(out / "report.json").find("sections.a.layer_height"), std::string::npos);
  // A setting that names nothing, or has no '=', is bad input.
  const Result bad = run("run " + (std::filesystem::temp_directory_path() / "bt_cli_pass.yaml").string() +
                         " --set sections.b.layer_height=4 -q -o " + out.string());
  EXPECT_EQ(bad.code, 2) << bad.output;
  EXPECT_NE(bad.output.find("no section named 'b'"), std::string::npos) << bad.output;
  EXPECT_EQ(run("slice --set oops -o -").code, 2);
}

TEST(Cli, SliceWritesTheProgram) {
  const auto out = std::filesystem::temp_directory_path() / "bt_cli_slice.nc";
  std::filesystem::remove(out);
  const Result r = run("slice -o " + out.string());
  EXPECT_EQ(r.code, 0) << r.output;
  std::ifstream f(out);
  std::string first;
  std::getline(f, first);
  EXPECT_EQ(first, "%");
}

// docs/parameters.md is generated from the parameter table; it must be what the program prints now.
TEST(Cli, ParametersDocIsCurrent) {
  const Result r = run("params");
  ASSERT_EQ(r.code, 0);
  EXPECT_NE(r.output.find("| `boundary.passes` | integer | `1` |"), std::string::npos)
      << r.output.substr(0, 2000);
  std::ifstream f(std::string(BEADTWIN_SOURCE_DIR) + "/docs/parameters.md");
  ASSERT_TRUE(f) << "docs/parameters.md is missing";
  const std::string doc((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_EQ(doc, r.output) << "regenerate it: beadtwin params > docs/parameters.md";
}

// docs/metrics.md is generated from the metric declarations; it must be what the program prints now.
TEST(Cli, MetricsDocIsCurrent) {
  const Result r = run("metrics");
  ASSERT_EQ(r.code, 0);
  EXPECT_NE(r.output.find("| `interfaces.too_cold_fraction` | fraction | lower | yes |"), std::string::npos)
      << r.output.substr(0, 2000);
  EXPECT_NE(r.output.find("| `sections.NAME.print_time_s` | s | lower | yes |"), std::string::npos)
      << r.output;
  std::ifstream f(std::string(BEADTWIN_SOURCE_DIR) + "/docs/metrics.md");
  ASSERT_TRUE(f) << "docs/metrics.md is missing";
  const std::string doc((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_EQ(doc, r.output) << "regenerate it: beadtwin metrics > docs/metrics.md";
}

// Inputs that would need absurd work are refused up front with the key and line to change.
TEST(Cli, AbsurdResolutionsAreInputErrors) {
  const std::string base =
      "name: tiny\nunits: {length: mm}\nmachine: lsam-ph15\nmaterial: cf-abs-20\n"
      "part:\n  box: {size: [120, 80, 15]}\n";
  const auto vox =
      write("bt_cli_vox.yaml", base +
                                   "output: {voxel_size: 0.0001 mm}\nsections:\n"
                                   "  - {name: a, z: [0, 15], layer_height: 5, bead_width: 20}\n");
  const Result r1 = run("run " + vox.string() + " -q -o /tmp/bt_cli_vox");
  EXPECT_EQ(r1.code, 2) << r1.output;
  EXPECT_NE(r1.output.find(vox.string() + ":7:"), std::string::npos) << r1.output;
  EXPECT_NE(r1.output.find("output.voxel_size"), std::string::npos) << r1.output;
  const auto layers = write("bt_cli_layers.yaml", base +
                                                      "sections:\n  - name: a\n    z: [0, 15]\n"
                                                      "    layer_height: 0.0001\n    bead_width: 20\n");
  const Result r2 = run("run " + layers.string() + " -q -o /tmp/bt_cli_layers");
  EXPECT_EQ(r2.code, 2) << r2.output;
  EXPECT_NE(r2.output.find(layers.string() + ":10:"), std::string::npos) << r2.output;
  EXPECT_NE(r2.output.find("150000 layers"), std::string::npos) << r2.output;
}

// `beadtwin check PROGRAM`: a program from another slicer, simulated as written, with the
// machine inferred and said so; with a baseline, both side by side; a program written as a Fanuc macro
// program (our own macro dialect) simulated through the interpreter.
TEST(Cli, CheckSimulatesAProgramAsItIsWritten) {
  const std::string sample = std::string(BEADTWIN_SOURCE_DIR) + "/tests/data/prusa_box.gcode";
  const auto out = std::filesystem::temp_directory_path() / "beadtwin_cli_check";
  std::filesystem::remove_all(out);
  const Result r = run("check " + sample + " -q -o " + out.string());
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("assumed machine desktop-fff"), std::string::npos) << r.output;
  const std::string report = read_file(out / "report.json");
  EXPECT_NE(report.find("\"program\""), std::string::npos);
  EXPECT_NE(report.find("assumed machine desktop-fff"), std::string::npos);  // in the report too
  EXPECT_TRUE(std::filesystem::exists(out / "program" / "fusion.png"));
  // A desktop bead's conduction time through its height is short against its layer time: one cell through
  // it resolves its cooling, and the report does not ask for more.
  EXPECT_EQ(report.find("thermal.cells_through: 2"), std::string::npos);

  // A macro program (layers in a WHILE loop) against the plain one as baseline, on the gantry.
  const auto yaml =
      write("beadtwin_cli_ring.yaml",
            "name: ring\nunits: {length: mm}\nmachine: lsam-ph15\nmaterial: cf-abs-20\n"
            "sections:\n  - name: ring\n    layers: 6\n    layer_height: 5\n    bead_width: 20\n"
            "    speed: 60 mm/s\n    outline: {points: [[0, 0], [300, 0], [300, 200], [0, 200]]}\n"
            "variants:\n  - name: plain\n  - name: macro\n    set: {machine.gcode.macro_loops: true}\n");
  const auto plain = std::filesystem::temp_directory_path() / "beadtwin_cli_ring_plain.nc";
  const auto macro = std::filesystem::temp_directory_path() / "beadtwin_cli_ring_macro.nc";
  ASSERT_EQ(run("slice " + yaml.string() + " --variant plain -o " + plain.string()).code, 0);
  ASSERT_EQ(run("slice " + yaml.string() + " --variant macro -o " + macro.string()).code, 0);
  ASSERT_NE(read_file(macro).find("WHILE"), std::string::npos);
  std::filesystem::remove_all(out);
  const Result both = run("check " + macro.string() + " --machine lsam-ph15 --baseline " + plain.string() +
                          " -q -o " + out.string());
  EXPECT_EQ(both.code, 0) << both.output;
  EXPECT_EQ(both.output.find("assumed machine"), std::string::npos) << both.output;
  const std::string two = read_file(out / "report.json");
  // A 5 mm CF-ABS bead's conduction time through its height (about 2 minutes) is not short against the
  // ring's layer time: the report says that one cell through it is optimistic, and how to check.
  EXPECT_NE(two.find("is not short against the layer time"), std::string::npos);
  EXPECT_NE(two.find("thermal.cells_through: 2"), std::string::npos);
  // The same part either way: the same commanded volume in both variants.
  const auto volume = [&](std::size_t from) {
    const std::size_t at = two.find("\"commanded_volume_mm3\":", from);
    return at == std::string::npos ? -1.0 : std::stod(two.substr(at + 23));
  };
  const std::size_t second = two.find("\"commanded_volume_mm3\":") + 1;
  EXPECT_GT(volume(0), 0);
  EXPECT_NEAR(volume(0), volume(second), 1e-6 * volume(0));

  EXPECT_EQ(run("check /nonexistent/program.gcode -q -o " + out.string()).code, 2);
  EXPECT_EQ(run("check " + sample + " --machine nosuchmachine -q -o " + out.string()).code, 2);
}

// The CI gate of docs/ci.md: a changed program checked against the old one with gates relative to it.
// Slowing the ring from 60 to 40 mm/s makes the print half as long again: a gate that allows 5 % fails the
// change, and one that allows 60 % passes it; gates also come from a file.
TEST(Cli, CheckGatesAChangeAgainstItsBaseline) {
  const auto yaml =
      write("beadtwin_cli_gate.yaml",
            "name: ring\nunits: {length: mm}\nmachine: lsam-ph15\nmaterial: cf-abs-20\n"
            "sections:\n  - name: ring\n    layers: 4\n    layer_height: 5\n    bead_width: 20\n"
            "    speed: 60 mm/s\n    outline: {points: [[0, 0], [300, 0], [300, 200], [0, 200]]}\n");
  const auto old_nc = std::filesystem::temp_directory_path() / "beadtwin_cli_gate_old.nc";
  const auto new_nc = std::filesystem::temp_directory_path() / "beadtwin_cli_gate_new.nc";
  ASSERT_EQ(run("slice " + yaml.string() + " -o " + old_nc.string()).code, 0);
  ASSERT_EQ(run("slice " + yaml.string() + " --set sections.ring.speed=40mm/s -o " + new_nc.string()).code,
            0);
  const auto out = std::filesystem::temp_directory_path() / "beadtwin_cli_gate_out";
  const std::string check = "check " + new_nc.string() + " --machine lsam-ph15 --baseline " +
                            old_nc.string() + " -q -o " + out.string();
  const Result tight = run(check + " --gate 'print_time_s <= baseline * 1.05'");
  EXPECT_EQ(tight.code, 1) << tight.output;
  EXPECT_NE(tight.output.find("gate failed in program: print_time_s"), std::string::npos) << tight.output;
  const std::string junit = read_file(out / "junit.xml");
  EXPECT_NE(junit.find("<failure"), std::string::npos);
  const auto gates = write("beadtwin_cli_gates.yaml", "- print_time_s <= baseline * 1.6\n- porosity < 0.1\n");
  const Result loose = run(check + " --gates " + gates.string());
  EXPECT_EQ(loose.code, 0) << loose.output;
  EXPECT_EQ(run(check + " --gate 'print_tme_s <= 1'").code, 2);
  EXPECT_EQ(run(check + " --gates /nonexistent/gates.yaml").code, 2);
}

// Two thin desktop beads (0.3 mm): the skin simplifies away at the 0.3 mm default tolerance. The run says
// so in a note (also in report.json) and writes no skin, instead of stopping with an internal error.
TEST(Cli, ThinBeadsLeaveNoSkinAndSaySo) {
  const auto program =
      write("bt_cli_thin.gcode", "G21\nG90\nM83\nG1 Z0.3 F600\nG1 X50 Y0 E2\nG1 X50 Y50 E2\nM30\n");
  const auto out = std::filesystem::temp_directory_path() / "bt_cli_thin";
  std::filesystem::remove_all(out);
  const Result r = run("check " + program.string() + " -o " + out.string());
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("no skin written"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out / "program" / "skin.ply"));
  EXPECT_NE(read_file(out / "report.json").find("no skin written"), std::string::npos);
  EXPECT_NE(read_file(out / "report.html").find("<h3>Notes</h3>"), std::string::npos);
}

// An output directory that cannot be made or written: exit code 2 at once, naming it and the option,
// before any work; nothing written.
TEST(Cli, UnwritableOutputDirectoryIsAnInputError) {
  const auto file = write("bt_cli_a_file", "not a directory\n");
  for (const std::string& out : {file.string() + "/out", std::string("/proc/beadtwin-out")}) {
    SCOPED_TRACE(out);
    const Result r = run("run -o " + out);
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("--out: cannot write the output here"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("[baseline]"), std::string::npos) << "the run started: " << r.output;
  }
  const Result slice = run("slice -o " + file.string() + "/program.nc");
  EXPECT_EQ(slice.code, 2) << slice.output;
  EXPECT_NE(slice.output.find("Not a directory"), std::string::npos) << slice.output;
}

// A scenario named without a directory finds the machine files beside it, as one named ./s.yaml does.
TEST(Cli, ScenarioInTheWorkingDirectoryFindsItsMachines) {
  const auto dir = std::filesystem::temp_directory_path() / "bt_cli_cwd";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "machines");
  std::filesystem::copy_file(
      std::filesystem::path(BEADTWIN_SOURCE_DIR) / "scenarios/data/machines/lsam-ph15.yaml",
      dir / "machines/my-gantry.yaml");
  std::ofstream(dir / "s.yaml") << "name: cwd\nunits: {length: mm}\nmachine: my-gantry\nmaterial: cf-abs-20\n"
                                   "part:\n  box: {size: [200, 150, 10]}\nsections:\n"
                                   "  - {name: all, z: part, layer_height: 5, bead_width: 20}\n";
  const Result r =
      beadtwin::testing::shell("cd " + dir.string() + " && " + BEADTWIN_BINARY + " slice s.yaml -o - 2>&1");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("G1"), std::string::npos) << r.output;
}

// report.json without what measures the run rather than the part: wall and stage times.
nlohmann::json without_timing(nlohmann::json j) {
  j.erase("wall_time_s");
  for (auto& v : j["variants"]) v.erase("stage_seconds");
  return j;
}

// The same part, whatever the threads: report.json equal in every number (timings aside) and summary.md
// equal, on one thread and on two, and on a second run.
TEST(Cli, ReportsDoNotDependOnThreadsOrRuns) {
  const auto scenario = write("bt_cli_threads.yaml", beadtwin::testing::small_box("threads"));
  std::vector<nlohmann::json> reports;
  std::vector<std::string> summaries;
  for (const char* threads : {"1", "2", "2"}) {
    const auto out =
        std::filesystem::temp_directory_path() / ("bt_cli_threads_" + std::to_string(reports.size()));
    std::filesystem::remove_all(out);
    const Result r = run("run " + scenario.string() + " -q --threads " + threads + " -o " + out.string());
    ASSERT_LE(r.code, 1) << r.output;
    reports.push_back(without_timing(nlohmann::json::parse(read_file(out / "report.json"))));
    summaries.push_back(read_file(out / "summary.md"));
  }
  EXPECT_EQ(reports[0], reports[1]) << nlohmann::json::diff(reports[0], reports[1]).dump(1).substr(0, 2000);
  EXPECT_EQ(reports[1], reports[2]) << nlohmann::json::diff(reports[1], reports[2]).dump(1).substr(0, 2000);
  EXPECT_EQ(summaries[0], summaries[1]);
  EXPECT_EQ(run("run --threads 0").code, 2);  // at least one
}

// Ctrl-C in the middle of a run: exit code 130, a line saying what it stopped, the previous run's report
// unchanged; the next run clears what the stopped one left half-written.
TEST(Cli, InterruptedRunKeepsThePreviousReport) {
  const auto out = std::filesystem::temp_directory_path() / "bt_cli_interrupt";
  std::filesystem::remove_all(out);
  const std::string part = std::string(BEADTWIN_SOURCE_DIR) + "/tests/bad/part.yaml";
  ASSERT_EQ(run("run " + part + " -q -o " + out.string()).code, 0);
  const std::string before = read_file(out / "report.json");
  // A stale temporary, as a run killed while writing a picture leaves one (no process has this id).
  std::ofstream(out / "baseline" / ".tmp-4999999-fusion.png") << "half a picture";

  // The default scenario takes several seconds; stopped after 3.
  const Result r =
      beadtwin::testing::shell(std::string(BEADTWIN_BINARY) + " run -q -o " + out.string() +
                               " 2>&1 & pid=$!; sleep 3; kill -INT $pid; wait $pid; echo \"exit=$?\"");
  EXPECT_NE(r.output.find("exit=130"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("interrupted: stopped during "), std::string::npos) << r.output;
  EXPECT_EQ(read_file(out / "report.json"), before);
  EXPECT_FALSE(std::filesystem::exists(out / "baseline" / ".tmp-4999999-fusion.png"));
}

TEST(Cli, ARunThatStopsPartWayLeavesThePreviousRunsFiles) {
  namespace fs = std::filesystem;
  const fs::path out = fs::temp_directory_path() / "bt_cli_staged";
  fs::remove_all(out);
  const std::string part = std::string(BEADTWIN_SOURCE_DIR) + "/tests/bad/part.yaml";
  ASSERT_EQ(run("run " + part + " -q -o " + out.string()).code, 0);
  const std::string report = read_file(out / "report.json");
  const std::string program = read_file(out / "baseline" / "program.nc");
  // A staging folder a killed run left (no process has this id).
  fs::create_directories(out / ".tmp-4999999-run" / "baseline");
  std::ofstream(out / ".tmp-4999999-run" / "baseline" / "program.nc") << "half a run";

  // The same part in two variants: the baseline now at 4 mm layers (a different program), then one whose
  // voxels cannot fit in memory, found in its deposit stage after the baseline has run and written its files.
  const fs::path scenario = fs::temp_directory_path() / "bt_cli_staged.yaml";
  std::ofstream(scenario)
      << "name: staged\nmachine: lsam-ph15\nmaterial: cf-abs-20\n"
      << "part: {mesh: " << BEADTWIN_SOURCE_DIR << "/tests/bad/part.stl}\n"
      << "output: {voxel_size: 5 mm}\n"
      << "sections:\n  - {name: all, z: part, layer_height: 4, bead_width: 20, "
         "boundary: {passes: 1}, fill: none}\n"
      << "variants:\n  - name: baseline\n  - name: fine\n    set: {output.voxel_size: 0.01}\n";
  const Result r = run("run " + scenario.string() + " -q -o " + out.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("over the memory budget"), std::string::npos) << r.output;
  EXPECT_EQ(read_file(out / "report.json"), report);
  EXPECT_EQ(read_file(out / "baseline" / "program.nc"), program);
  EXPECT_FALSE(fs::exists(out / "fine"));
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_FALSE(e.path().filename().string().starts_with(".tmp-")) << e.path();

  // The same scenario without the bad variant completes: every file moves into place.
  ASSERT_EQ(run("run " + scenario.string() + " --variant baseline -q -o " + out.string()).code, 0);
  EXPECT_NE(read_file(out / "baseline" / "program.nc"), program);
  EXPECT_NE(read_file(out / "report.json"), report);
}

}  // namespace
