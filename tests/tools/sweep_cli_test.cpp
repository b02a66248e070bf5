// `beadtwin sweep` as a user runs it: every combination runs as its own `beadtwin run` and
// measures what that run measures alone; a variant that fails is reported and the sweep goes on; a sweep
// started again keeps what ran; bad input stops it before anything runs; under mpirun the ranks give the
// same records as the plain run.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/read_file.hpp"
#include "tests/shell.hpp"

namespace {

namespace fs = std::filesystem;
using beadtwin::testing::read_file;
using nlohmann::json;

beadtwin::testing::ShellResult beadtwin_cmd(const std::string& args) {
  return beadtwin::testing::shell(std::string(BEADTWIN_BINARY) + " " + args + " 2>&1");
}

// A three-layer box that runs in about a second, with a gate that holds at 5 mm layers only.
fs::path tiny_scenario() {
  const fs::path p = fs::temp_directory_path() / "bt_sweep_tiny.yaml";
  std::ofstream(p) << "name: tiny\nunits: {length: mm}\nmachine: lsam-ph15\nmaterial: cf-abs-20\n"
                      "part:\n  box: {size: [120, 80, 15]}\n"
                      "output: {voxel_size: 2.5 mm}\n"
                      "render: {width: 120, height: 80}\n"
                      "sections:\n  - {name: a, z: [0, 15], layer_height: 5, bead_width: 20, boundary: "
                      "{passes: 1}, fill: {angle: 0 deg}}\n"
                      "gates:\n  - layers == 3\n";
  return p;
}

json sweep_json(const fs::path& out) {
  return json::parse(read_file(out / "sweep.json"));
}

const json& variant(const json& sweep, const std::string& name) {
  for (const json& v : sweep["variants"])
    if (v["name"] == name) return v;
  throw std::runtime_error("no variant " + name);
}

TEST(Sweep, RunsEveryCombinationAsItsOwnRunAndReportsThemTogether) {
  const fs::path out = fs::temp_directory_path() / "bt_sweep_grid";
  fs::remove_all(out);
  const auto r =
      beadtwin_cmd("sweep " + tiny_scenario().string() +
                   " --set sections.a.layer_height=5mm,3.75mm --set sections.a.bead_width=20mm,24mm"
                   " --pareto print_time_s,interfaces.too_cold_fraction --jobs 2 -o " +
                   out.string());
  // Two of the four variants print four layers: the scenario's gate fails there, so the sweep does.
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("report: " + (out / "sweep.html").string()), std::string::npos) << r.output;
  const json s = sweep_json(out);
  ASSERT_EQ(s["variants"].size(), 4u) << s.dump(1);
  EXPECT_EQ(s["counts"]["passed"], 2);
  EXPECT_EQ(s["counts"]["gate_failed"], 2);
  EXPECT_EQ(s["counts"]["failed"], 0);
  EXPECT_EQ(variant(s, "v001")["settings"][0]["value"], "5mm");
  EXPECT_EQ(variant(s, "v003")["status"], "gate failed");
  EXPECT_EQ(variant(s, "v003")["values"]["layers"], 4);
  for (const char* file : {"sweep.html", "summary.md", "junit.xml", "variants/v004/report.html"})
    EXPECT_TRUE(fs::exists(out / file)) << file;
  EXPECT_FALSE(s["pareto"]["front"].empty());

  // A variant measures in the sweep what it measures run alone.
  const fs::path alone = fs::temp_directory_path() / "bt_sweep_alone";
  fs::remove_all(alone);
  const auto single = beadtwin_cmd(
      "run " + tiny_scenario().string() +
      " --set sections.a.layer_height=3.75mm --set sections.a.bead_width=24mm -q -o " + alone.string());
  ASSERT_EQ(single.code, 1) << single.output;
  const json report = json::parse(read_file(alone / "report.json"));
  EXPECT_EQ(variant(s, "v004")["values"], report["variants"][0]["values"]);
}

TEST(Sweep, AVariantThatFailsIsReportedAndTheSweepGoesOnAndResumes) {
  const fs::path out = fs::temp_directory_path() / "bt_sweep_resume";
  fs::remove_all(out);
  // The second combination's memory budget cannot hold the deposit: that run stops with a message, late
  // (the budget is checked when the deposit starts), as a variant on a cluster might.
  const fs::path combos = fs::temp_directory_path() / "bt_sweep_combos.yaml";
  std::ofstream(combos) << "- {output.memory_budget: 0}\n- {output.memory_budget: 0.000001}\n";
  const std::string cmd = "sweep " + tiny_scenario().string() + " --combinations " + combos.string() +
                          " --set sections.a.speed=1in/s,2in/s -o " + out.string();
  const auto first = beadtwin_cmd(cmd);
  EXPECT_EQ(first.code, 1) << first.output;
  json s = sweep_json(out);
  ASSERT_EQ(s["variants"].size(), 4u);
  EXPECT_EQ(s["counts"]["passed"], 2) << s.dump(1);
  EXPECT_EQ(s["counts"]["failed"], 2);
  const json& failed = variant(s, "v003");
  EXPECT_EQ(failed["status"], "failed to run");
  EXPECT_EQ(failed["exit_code"], 2);
  EXPECT_NE(failed["message"].get<std::string>().find("memory"), std::string::npos) << failed["message"];
  EXPECT_NE(read_file(out / "sweep.html").find("did not run to the end"), std::string::npos);

  // Started again: the two that ran are kept (their reports untouched), the two that failed run again.
  const auto written = fs::last_write_time(out / "variants/v001/report.json");
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const auto again = beadtwin_cmd(cmd);
  EXPECT_EQ(again.code, 1) << again.output;
  EXPECT_NE(again.output.find("4 variants (2 from an earlier run)"), std::string::npos) << again.output;
  EXPECT_EQ(fs::last_write_time(out / "variants/v001/report.json"), written);
  s = sweep_json(out);
  EXPECT_EQ(s["resumed"], 2);
  EXPECT_EQ(variant(s, "v001")["values"]["layers"], 3);

  // A third value renumbers the grid: the variants that ran keep their runs, matched by their settings and
  // moved to their new names, and only the new ones run.
  const auto wider = beadtwin_cmd("sweep " + tiny_scenario().string() + " --combinations " + combos.string() +
                                  " --set sections.a.speed=3in/s,1in/s,2in/s -o " + out.string());
  EXPECT_EQ(wider.code, 1) << wider.output;
  EXPECT_NE(wider.output.find("6 variants (2 from an earlier run)"), std::string::npos) << wider.output;
  s = sweep_json(out);
  ASSERT_EQ(s["variants"].size(), 6u);
  EXPECT_EQ(variant(s, "v002")["settings"][1]["value"], "1in/s");
  EXPECT_EQ(variant(s, "v002")["values"]["layers"], 3);
  EXPECT_EQ(fs::last_write_time(out / "variants/v002/report.json"), written);  // was v001
  EXPECT_NE(read_file(out / "variants/v002/report.json").find("\"1in/s\""), std::string::npos);
}

TEST(Sweep, StartedAgainWithEveryVariantDoneItSaysNothingIsLeftToRun) {
  const fs::path out = fs::temp_directory_path() / "bt_sweep_done";
  fs::remove_all(out);
  const std::string cmd =
      "sweep " + tiny_scenario().string() + " --set sections.a.speed=1in/s,2in/s --jobs 2 -o " + out.string();
  const auto first = beadtwin_cmd(cmd);
  ASSERT_EQ(first.code, 0) << first.output;
  EXPECT_NE(first.output.find("2 local processes"), std::string::npos) << first.output;
  const auto again = beadtwin_cmd(cmd);
  EXPECT_EQ(again.code, 0) << again.output;
  EXPECT_NE(again.output.find("nothing left to run"), std::string::npos) << again.output;
  EXPECT_NE(sweep_json(out)["engine"].get<std::string>().find("nothing left to run"), std::string::npos);
  EXPECT_EQ(sweep_json(out)["resumed"], 2);
}

TEST(Sweep, AnEditedMaterialFileBesideTheScenarioStartsItAfresh) {
  // The scenario takes its material from a file beside it; the sweep's resume must see that file change, as
  // it sees the scenario's text change: the variants' results depend on it.
  const fs::path dir = fs::temp_directory_path() / "bt_sweep_inputs";
  fs::remove_all(dir);
  fs::create_directories(dir / "materials");
  const std::string shipped =
      read_file(fs::path(BEADTWIN_SOURCE_DIR) / "scenarios/data/materials/cf-abs-20.yaml");
  std::ofstream(dir / "materials/mine.yaml") << shipped;
  std::string text = read_file(tiny_scenario());
  text.replace(text.find("material: cf-abs-20"), 19, "material: mine");
  std::ofstream(dir / "box.yaml") << text;
  const fs::path out = dir / "out";
  const std::string cmd =
      "sweep " + (dir / "box.yaml").string() + " --set sections.a.speed=1in/s,2in/s -o " + out.string();
  const auto first = beadtwin_cmd(cmd);
  ASSERT_EQ(first.code, 0) << first.output;
  const auto same = beadtwin_cmd(cmd);
  ASSERT_EQ(same.code, 0) << same.output;
  EXPECT_EQ(sweep_json(out)["resumed"], 2);
  const double mass = sweep_json(out)["variants"][0]["values"]["mass_kg"].get<double>();

  // A denser material: both variants run again and weigh more.
  std::string denser = shipped;
  denser.replace(denser.find("density: 1140 kg/m3"), 19, "density: 1300 kg/m3");
  // Its plausible range with it: a file's value must lie in its own range.
  const std::string range = "density: [1100 kg/m3, 1180 kg/m3]";
  denser.replace(denser.find(range), range.size(), "density: [1250 kg/m3, 1350 kg/m3]");
  std::ofstream(dir / "materials/mine.yaml") << denser;
  const auto edited = beadtwin_cmd(cmd);
  ASSERT_EQ(edited.code, 0) << edited.output;
  EXPECT_EQ(sweep_json(out)["resumed"], 0) << edited.output;
  EXPECT_NEAR(sweep_json(out)["variants"][0]["values"]["mass_kg"].get<double>(), mass * 1300 / 1140,
              mass * 1e-9);
}

TEST(Sweep, BadInputStopsItBeforeAnythingRuns) {
  const fs::path out = fs::temp_directory_path() / "bt_sweep_bad";
  const std::string scenario = tiny_scenario().string();
  struct Case {
    std::string args, says;
  };
  for (const Case& c : std::vector<Case>{
           {"", "nothing to sweep"},
           {"--set sections.a.layer_height=5mm,-1mm", "layer_height"},
           {"--set sections.b.layer_height=5mm", "no section named 'b'"},
           {"--set sections.a.layer_height=5mm,,4mm", "value 2 of 3 is empty"},
           {"--set sections.a.layer_height=5mm --pareto print_time_s", "expected two metrics"},
           {"--set sections.a.layer_height=5mm --sort speediness", "unknown metric 'speediness'"},
           {"--set sections.a.layer_height=5mm --variant nope", "no variant named 'nope'"},
           {"--set sections.a.layer_height=5mm --combinations /nonexistent.yaml", "--combinations"},
       }) {
    fs::remove_all(out);
    const auto r = beadtwin_cmd("sweep " + scenario + " " + c.args + " -o " + out.string());
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(out / "variants")) << c.args;
  }
}

#ifdef BEADTWIN_MPIEXEC
// Under mpirun, rank 0 hands the variants to rank 1; the records are those of the plain run.
TEST(Sweep, UnderMpiRankZeroHandsOutTheVariantsAndTheRecordsMatchThePlainRun) {
  const fs::path plain = fs::temp_directory_path() / "bt_sweep_plain",
                 mpi = fs::temp_directory_path() / "bt_sweep_mpi";
  fs::remove_all(plain);
  fs::remove_all(mpi);
  const std::string args =
      " sweep " + tiny_scenario().string() + " --set sections.a.bead_width=20mm,24mm,28mm -q -o ";
  const auto p = beadtwin_cmd(args + plain.string());
  ASSERT_EQ(p.code, 0) << p.output;
  const auto m =
      beadtwin::testing::shell(std::string(BEADTWIN_MPIEXEC) + " -n 2 --allow-run-as-root --oversubscribe " +
                               BEADTWIN_BINARY + args + mpi.string() + " 2>&1");
  ASSERT_EQ(m.code, 0) << m.output;
  const json a = sweep_json(plain), b = sweep_json(mpi);
  EXPECT_NE(b["engine"].get<std::string>().find("MPI, 2 ranks"), std::string::npos) << b["engine"];
  ASSERT_EQ(a["variants"].size(), b["variants"].size());
  for (std::size_t i = 0; i < a["variants"].size(); ++i) {
    EXPECT_EQ(a["variants"][i]["values"], b["variants"][i]["values"]) << i;
    EXPECT_NE(b["variants"][i]["worker"].get<std::string>().find("rank 1"), std::string::npos);
  }
  // A failing variant under MPI is reported too, and the sweep's exit code says so.
  const auto bad =
      beadtwin::testing::shell(std::string(BEADTWIN_MPIEXEC) + " -n 2 --allow-run-as-root --oversubscribe " +
                               BEADTWIN_BINARY + " sweep " + tiny_scenario().string() +
                               " --set output.memory_budget=0,0.000001 -q -o " + mpi.string() + " 2>&1");
  EXPECT_EQ(bad.code, 1) << bad.output;
  EXPECT_EQ(sweep_json(mpi)["counts"]["failed"], 1);
  // Bad input stops every rank with rank 0's message and exit code 2, rather than leave rank 1 waiting.
  const auto typo =
      beadtwin::testing::shell(std::string(BEADTWIN_MPIEXEC) + " -n 2 --allow-run-as-root --oversubscribe " +
                               BEADTWIN_BINARY + " sweep " + tiny_scenario().string() +
                               " --set sections.b.layer_height=5mm -o " + mpi.string() + " 2>&1");
  EXPECT_NE(typo.output.find("no section named 'b'"), std::string::npos) << typo.output;
  EXPECT_NE(typo.output.find("Exit code:    2"), std::string::npos) << typo.output;
}

// `beadtwin run` under mpirun: the two ranks share the thermal solve (thermal/heat.hpp), rank 0 writes the
// outputs, and every value of the report is the plain run's within the solver's tolerance.
TEST(RunUnderMpi, TheRanksShareTheThermalSolveAndTheReportIsThePlainRunsWithinTheSolversTolerance) {
  const fs::path plain = fs::temp_directory_path() / "bt_run_plain",
                 mpi = fs::temp_directory_path() / "bt_run_mpi";
  fs::remove_all(plain);
  fs::remove_all(mpi);
  const std::string args = " run " + tiny_scenario().string() + " -q -o ";
  const auto p = beadtwin_cmd(args + plain.string());
  ASSERT_EQ(p.code, 0) << p.output;
  const std::string mpirun =
      std::string(BEADTWIN_MPIEXEC) + " -n 2 --allow-run-as-root --oversubscribe " + BEADTWIN_BINARY;
  const auto m = beadtwin::testing::shell(mpirun + args + mpi.string() + " 2>&1");
  ASSERT_EQ(m.code, 0) << m.output;
  const json a = json::parse(read_file(plain / "report.json")),
             b = json::parse(read_file(mpi / "report.json"));
  const json& va = a["variants"][0]["values"];
  const json& vb = b["variants"][0]["values"];
  ASSERT_EQ(va.size(), vb.size());
  for (const auto& [key, value] : va.items()) {
    ASSERT_TRUE(vb.contains(key)) << key;
    const double x = value.get<double>(), y = vb[key].get<double>();
    EXPECT_NEAR(x, y, 1e-3 * std::max(1.0, std::abs(x))) << key;
  }
  const auto notes = b["variants"][0]["notes"].dump();
  EXPECT_NE(notes.find("solved across 2 MPI ranks"), std::string::npos) << notes;
  // One set of outputs, rank 0's: the same files as the plain run's.
  const auto files = [](const fs::path& dir) {
    std::vector<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(dir))
      out.push_back(fs::relative(e.path(), dir).string());
    std::sort(out.begin(), out.end());
    return out;
  };
  EXPECT_EQ(files(plain), files(mpi));
  // Bad input found by rank 0 alone (an output folder that is a file) stops every rank with exit code 2.
  const fs::path taken = fs::temp_directory_path() / "bt_run_mpi_file";
  std::ofstream(taken) << "not a folder\n";
  const auto bad = beadtwin::testing::shell(mpirun + args + taken.string() + " 2>&1");
  EXPECT_NE(bad.output.find("Exit code:    2"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("--out"), std::string::npos) << bad.output;
}
#endif

}  // namespace
