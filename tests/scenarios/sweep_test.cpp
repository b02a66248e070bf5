// Sweeps: the --set grid and the combinations file expand to the variants a process engineer
// asked for, every input mistake stops with a message before anything runs, the Pareto front is the set no
// variant beats, and the reports carry every variant (junit.xml valid JUnit).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "scenarios/run.hpp"
#include "scenarios/sweep.hpp"
#include "tests/scenarios/report_checks.hpp"

namespace beadtwin::scenarios {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::vector<std::string> values_of(const std::vector<SweepPoint>& points, const std::string& key) {
  std::vector<std::string> out;
  for (const SweepPoint& p : points)
    for (const Setting& s : p.settings)
      if (s.key == key) out.push_back(s.value);
  return out;
}

fs::path write(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / name;
  std::ofstream(p) << text;
  return p;
}

// The InputError `f` throws, or a failure.
template <class F>
InputError input_error(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError";
  return InputError("none");
}

TEST(SweepAxis, SplitsTheValuesAtTheCommasOutsideBracketsAndQuotes) {
  const SweepAxis a = parse_sweep_axis("sections.walls.bead_width=18mm, 20 mm,22mm");
  EXPECT_EQ(a.key, "sections.walls.bead_width");
  EXPECT_EQ(a.values, (std::vector<std::string>{"18mm", "20 mm", "22mm"}));
  EXPECT_EQ(parse_sweep_axis("part.origin=[0, 5],[10, 5]").values,
            (std::vector<std::string>{"[0, 5]", "[10, 5]"}));
  EXPECT_EQ(parse_sweep_axis("a={x: 1, y: 2},'p,q',\"r,s\"").values,
            (std::vector<std::string>{"{x: 1, y: 2}", "'p,q'", "\"r,s\""}));
  EXPECT_EQ(parse_sweep_axis("output.voxel_size=2.5mm").values.size(), 1u);

  const InputError empty = input_error([] { parse_sweep_axis("sections.walls.speed=1in/s,,2in/s"); });
  EXPECT_EQ(empty.key(), "--set");
  EXPECT_NE(std::string(empty.what()).find("value 2 of 3 is empty"), std::string::npos) << empty.what();
  EXPECT_EQ(input_error([] { parse_sweep_axis("no-equals-sign"); }).key(), "--set");
}

TEST(SweepExpansion, IsTheFullFactorialWithTheLastAxisTurningFastest) {
  const std::vector<SweepAxis> axes = {{"a", {"1", "2"}}, {"b", {"x", "y", "z"}}};
  const std::vector<SweepPoint> points = expand_sweep(axes, {});
  ASSERT_EQ(points.size(), 6u);
  EXPECT_EQ(points.front().name, "v001");
  EXPECT_EQ(points.back().name, "v006");
  EXPECT_EQ(values_of(points, "a"), (std::vector<std::string>{"1", "1", "1", "2", "2", "2"}));
  EXPECT_EQ(values_of(points, "b"), (std::vector<std::string>{"x", "y", "z", "x", "y", "z"}));
  for (const SweepPoint& p : points) EXPECT_EQ(p.settings.size(), 2u);

  // Each combination of a file crossed with the grid; the file's settings first.
  const std::vector<std::vector<Setting>> rows = {{{"c", "10"}}, {{"c", "20"}, {"d", "on"}}};
  const std::vector<SweepPoint> crossed = expand_sweep({{"a", {"1", "2"}}}, rows);
  ASSERT_EQ(crossed.size(), 4u);
  EXPECT_EQ(values_of(crossed, "c"), (std::vector<std::string>{"10", "10", "20", "20"}));
  EXPECT_EQ(values_of(crossed, "a"), (std::vector<std::string>{"1", "2", "1", "2"}));
  EXPECT_EQ(crossed[3].settings.size(), 3u);
  EXPECT_EQ(expand_sweep({}, rows).size(), 2u);

  // A key set by both, or too many variants: stopped before anything runs.
  EXPECT_EQ(input_error([&] { expand_sweep({{"c", {"1"}}}, rows); }).key(), "c");
  const std::vector<std::string> many(50, "1");
  const InputError huge = input_error([&] { expand_sweep({{"a", many}, {"b", many}, {"c", many}}, {}); });
  EXPECT_NE(std::string(huge.what()).find("125000 variants"), std::string::npos) << huge.what();
}

TEST(SweepCombinations, ReadsAListOfSettingMapsAndNamesTheLineOfAMistake) {
  const auto rows =
      load_sweep_combinations(write("bt_combos.yaml",
                                    "# two ways to print the walls\n"
                                    "- {sections.walls.bead_width: 20 mm, sections.walls.speed: 1.2 in/s}\n"
                                    "- sections.walls.bead_width: 24 mm\n"
                                    "  part.origin: [0, 5, 0]\n"));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0][1].key, "sections.walls.speed");
  EXPECT_EQ(rows[0][1].value, "1.2 in/s");
  EXPECT_EQ(rows[1][1].value, "[0, 5, 0]");
  EXPECT_EQ(load_sweep_combinations(write("bt_combos_map.yaml", "combinations:\n  - {a: 1}\n")).size(), 1u);

  const InputError not_map =
      input_error([] { load_sweep_combinations(write("bt_combos_bad.yaml", "- {a: 1}\n- just text\n")); });
  EXPECT_EQ(not_map.where().line, 2);
  EXPECT_NE(std::string(not_map.what()).find("each a map of settings"), std::string::npos);
  const InputError twice = input_error(
      [] { load_sweep_combinations(write("bt_combos_twice.yaml", "- {a: 1, b: 2}\n- {b: 1, b: 2}\n")); });
  EXPECT_EQ(twice.where().line, 2);
  EXPECT_EQ(input_error([] { load_sweep_combinations(write("bt_combos_empty.yaml", "[]\n")); }).key(),
            "combinations");
  EXPECT_EQ(input_error([] { load_sweep_combinations("/nonexistent/combos.yaml"); }).key(), "--combinations");
}

TEST(SweepObjective, NamesAGateMetricAndWhichWayIsBetter) {
  EXPECT_FALSE(parse_objective("porosity", "--sort").maximise);
  const Objective healing = parse_objective("interfaces.min_healing:max", "--sort");
  EXPECT_EQ(healing.metric, "interfaces.min_healing");
  EXPECT_TRUE(healing.maximise);
  EXPECT_EQ(parse_objective("sections.walls.print_time_s:min", "--pareto").metric,
            "sections.walls.print_time_s");
  EXPECT_EQ(input_error([] { parse_objective("speediness", "--sort"); }).key(), "--sort");
  EXPECT_NE(std::string(input_error([] { parse_objective("porosity:up", "--pareto"); }).what())
                .find(":min or :max"),
            std::string::npos);
}

SweepRecord ran(const std::string& name, double time, double cold) {
  SweepRecord r;
  r.name = name;
  r.status = SweepStatus::kPassed;
  r.exit_code = 0;
  r.values = {{"print_time_s", time}, {"interfaces.too_cold_fraction", cold}, {"layers", 3}};
  return r;
}

TEST(SweepPareto, KeepsTheVariantsNoOtherBeatsOnBothMetrics) {
  std::vector<SweepRecord> rs = {ran("a", 100, 0.30), ran("b", 120, 0.10), ran("c", 110, 0.30),
                                 ran("d", 150, 0.00), ran("e", 160, 0.05), ran("f", 90, 0.50),
                                 ran("g", 100, 0.30)};
  SweepRecord failed;
  failed.name = "x";  // did not run: never on the front, whatever it would have measured
  rs.push_back(failed);
  const Objective time{"print_time_s", false}, cold{"interfaces.too_cold_fraction", false};
  // f (fastest), a and g (equal, neither beats the other), b, d (no cold joints); c is beaten by a, e by d.
  EXPECT_EQ(pareto_front(rs, time, cold), (std::vector<std::size_t>{5, 0, 6, 1, 3}));
  // Larger is better on y: the front turns over.
  EXPECT_EQ(pareto_front(rs, time, {"interfaces.too_cold_fraction", true}), (std::vector<std::size_t>{5}));
  EXPECT_EQ(pareto_front(rs, {"print_time_s", true}, cold), (std::vector<std::size_t>{4, 3}));
  // A metric no record measured: no front.
  EXPECT_TRUE(pareto_front(rs, time, {"porosity", false}).empty());
}

TEST(SweepRecords, RoundTripThroughJsonAndTakeTheirGates) {
  SweepRecord r = ran("v002", 123.5, 0.25);
  r.settings = {{"sections.walls.bead_width", "20 mm"}, {"part.origin", "[0, 5]"}};
  r.worker = "rank 1 on node7";
  r.wall_time_s = 4.5;
  r.message = "a \"quoted\" line\nand another";
  const SweepRecord back = parse_sweep_record(sweep_record_json(r), "test");
  EXPECT_EQ(back.name, r.name);
  ASSERT_EQ(back.settings.size(), 2u);
  EXPECT_EQ(back.settings[1].value, "[0, 5]");
  EXPECT_EQ(back.values, r.values);
  EXPECT_EQ(back.status, SweepStatus::kPassed);
  EXPECT_EQ(back.worker, r.worker);
  EXPECT_EQ(back.message, r.message);
  EXPECT_THROW(parse_sweep_record("{\"name\": 3}", "test"), InputError);

  // Gates: absolute ones on every record, relative ones against the record named baseline.
  std::vector<SweepRecord> rs = {ran("baseline", 100, 0.1), ran("v001", 104, 0.2), ran("v002", 110, 0.0)};
  SweepRecord killed;
  killed.name = "v003";
  killed.message = "killed";
  rs.push_back(killed);
  const std::vector<Gate> gates = {parse_gate_text("print_time_s <= baseline * 1.05", {"t", 1, 1}),
                                   parse_gate_text("interfaces.too_cold_fraction < 0.15", {"t", 2, 1})};
  apply_sweep_gates(rs, gates);
  EXPECT_EQ(rs[0].status, SweepStatus::kPassed);
  EXPECT_EQ(rs[1].status, SweepStatus::kGateFailed);  // too cold
  EXPECT_EQ(rs[2].status, SweepStatus::kGateFailed);  // too slow
  EXPECT_NE(rs[2].gates[0].message.find("baseline's: 100"), std::string::npos) << rs[2].gates[0].message;
  EXPECT_EQ(rs[3].status, SweepStatus::kFailed);
  EXPECT_TRUE(rs[3].gates.empty());
}

TEST(SweepRecords, ComeFromTheVariantsReportOrItsLog) {
  const fs::path dir = fs::temp_directory_path() / "bt_sweep_record";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const SweepPoint point{"v001", {{"a", "1"}}};
  // No report: failed, whatever the exit code said.
  EXPECT_EQ(record_of_run(point, dir, 0, "").status, SweepStatus::kFailed);
  std::ofstream(dir / "report.json") << json({{"variants", {{{"values", {{"porosity", 0.02}}}}}}}).dump();
  const SweepRecord r = record_of_run(point, dir, 1, "");
  EXPECT_TRUE(r.ran());
  EXPECT_EQ(r.values.at("porosity"), 0.02);
  const SweepRecord bad = record_of_run(point, dir, 2, std::string(5000, 'x') + "\nerror: the last line\n");
  EXPECT_FALSE(bad.ran());
  EXPECT_LT(bad.message.size(), 2100u);
  EXPECT_NE(bad.message.find("error: the last line"), std::string::npos);
  EXPECT_NE(record_of_run(point, dir, -1, "").message.find("signal"), std::string::npos);
}

SweepResult made_up_sweep() {
  SweepResult r;
  r.scenario_name = "walls & <floors>";
  r.scenario_file = "box.yaml";
  r.base_variant = "baseline";
  r.axes = {{"sections.walls.bead_width", {"18 mm", "20 mm", "22 mm"}},
            {"sections.walls.speed", {"1 in/s", "2 in/s"}}};
  r.gates = {parse_gate_text("interfaces.too_cold_fraction < 0.2", {"t", 1, 1})};
  r.sort = {"print_time_s", false};
  r.pareto = {{"print_time_s", false}, {"interfaces.too_cold_fraction", false}};
  r.engine = "2 local processes";
  const auto points = expand_sweep(r.axes, {});
  for (std::size_t i = 0; i < points.size(); ++i) {
    SweepRecord rec =
        ran(points[i].name, 200.0 - 10.0 * static_cast<double>(i), 0.05 * static_cast<double>(i));
    rec.settings = points[i].settings;
    r.records.push_back(rec);
  }
  r.records[4].status = SweepStatus::kFailed;
  r.records[4].values.clear();
  r.records[4].exit_code = 2;
  r.records[4].message = "error: the deposit needs 9 GB, more than the budget <1 GB>";
  apply_sweep_gates(r.records, r.gates);
  return r;
}

TEST(SweepReports, ListEveryVariantSortedWithItsFrontAndGates) {
  const SweepResult r = made_up_sweep();
  EXPECT_FALSE(r.passed());
  const json j = json::parse(sweep_json(r));
  EXPECT_EQ(j["counts"]["variants"], 6);
  EXPECT_EQ(j["counts"]["passed"], 4);       // v001..v004: too_cold 0, .05, .1, .15
  EXPECT_EQ(j["counts"]["gate_failed"], 1);  // v006: 0.25
  EXPECT_EQ(j["counts"]["failed"], 1);       // v005
  // Faster and colder down the list: every variant that ran is on the front.
  EXPECT_EQ(j["pareto"]["front"], json({"v006", "v004", "v003", "v002", "v001"}));

  const std::string html = sweep_html(r);
  // Sorted by print time, fastest first; the one that did not run last, its error shown and escaped.
  EXPECT_LT(html.find(">v006<"), html.find(">v004<"));
  EXPECT_LT(html.find(">v001<"), html.find("<td class=l>v005"));
  EXPECT_NE(html.find("more than the budget &lt;1 GB&gt;"), std::string::npos);
  EXPECT_NE(html.find("walls &amp; &lt;floors&gt;"), std::string::npos);
  const std::vector<json> plots = testing::report_plots(html);
  ASSERT_EQ(plots.size(), 1u);
  EXPECT_EQ(plots[0]["kind"], "pareto");
  EXPECT_EQ(plots[0]["front"].size(), 5u);
  EXPECT_EQ(plots[0]["points"].size(), 5u);  // every variant that ran, the front's too (to mark its gates)

  const std::string md = sweep_summary_md(r);
  EXPECT_NE(md.find("**failed**"), std::string::npos);
  EXPECT_NE(md.find("| 1 | v006 |"), std::string::npos) << md;

  const fs::path junit = fs::temp_directory_path() / "bt_sweep_junit.xml";
  std::ofstream(junit, std::ios::binary) << sweep_junit_xml(r);
  const testing::XmlDoc doc = testing::read_junit(junit);
  ASSERT_TRUE(doc);
  EXPECT_EQ(testing::xpath_number(doc.get(), "count(//testsuite)"), 6);
  EXPECT_EQ(testing::xpath_number(doc.get(), "count(//failure)"), 1);
  EXPECT_EQ(testing::xpath_number(doc.get(), "count(//error)"), 1);
}

}  // namespace
}  // namespace beadtwin::scenarios
