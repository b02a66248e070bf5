// Parameter sweeps (`beadtwin sweep`, docs/usage.md "sweep"): the variants a sweep runs — the full factorial
// of the values given with --set KEY=V1,V2,... and the explicit combinations of a file — and what each one
// measured, gathered into one report: a table sorted by a chosen metric, the Pareto front of two chosen
// metrics, and the gates applied to every variant.
//
// A sweep is a list of points; each point is the scenario's base variant with its settings applied after
// the variant's own (as --set does for `beadtwin run`). How the points are run — local processes, or MPI
// ranks — is the command line's business (tools/sweep_runner.hpp); this file knows only the points and
// their records, so the same records make the same report however they were run.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "scenarios/input/result.hpp"
#include "scenarios/input/scenario.hpp"
#include "scenarios/input/sweep_spec.hpp"

namespace beadtwin::scenarios {

enum class SweepStatus {
  kPassed,      // ran, every gate passed
  kGateFailed,  // ran, a gate failed
  kFailed,      // did not run to the end: bad input found late, an internal error, killed
};
std::string_view to_string(SweepStatus status);

// What a sweep keeps of one variant's run (the variant's own output folder has the rest).
struct SweepRecord {
  std::string name;
  std::vector<Setting> settings;
  SweepStatus status = SweepStatus::kFailed;
  int exit_code = -1;   // of the variant's run; -1 when it did not exit (killed by a signal)
  std::string message;  // why it failed: the end of its log
  MetricValues values;  // what it measured (Metrics::values); empty when it failed
  std::vector<GateResult> gates;
  double wall_time_s = 0;
  std::string worker;  // where it ran: "local", or "rank 3 on node7"
  bool ran() const { return status != SweepStatus::kFailed; }
  // What it measured of `metric`; nullopt when it did not run or did not measure it.
  std::optional<double> value(const std::string& metric) const;
};

// The record as JSON text (one line) and back: what a worker rank sends to rank 0, and what a variant's
// sweep.json keeps for a resumed sweep. parse_sweep_record throws InputError (file `where`) on text that is
// not a record.
std::string sweep_record_json(const SweepRecord& record);
SweepRecord parse_sweep_record(const std::string& text, const std::string& where);

// The record of a point whose run ended with `exit_code` (-1: killed), its report in `variant_dir`: with
// exit code 0 or 1 (ran; gates decide) the values of its report.json; otherwise failed, with the end of
// `log` as the reason. A report that is missing or unreadable makes it failed too.
SweepRecord record_of_run(const SweepPoint& point, const std::filesystem::path& variant_dir, int exit_code,
                          const std::string& log);

// The gates applied to every record that ran, those relative to the baseline against the record named
// "baseline" (the base variant as the scenario has it, which a sweep with such gates runs first); sets each
// record's gates and status.
void apply_sweep_gates(std::vector<SweepRecord>& records, const std::vector<Gate>& gates);

// Indices of the records on the Pareto front of (x, y): those that ran and measured both, and that no
// other such record matches or beats on both with a strict gain on one. Sorted by x, best first.
std::vector<std::size_t> pareto_front(const std::vector<SweepRecord>& records, const Objective& x,
                                      const Objective& y);

// A whole sweep, for its report.
struct SweepResult {
  std::string scenario_name;
  std::string scenario_file;
  std::string base_variant;
  std::vector<SweepAxis> axes;
  std::size_t combinations = 0;  // rows from the combinations file
  std::vector<Gate> gates;       // the scenario's and the command line's, applied to every variant
  Objective sort;
  std::optional<std::pair<Objective, Objective>> pareto;
  std::vector<SweepRecord> records;  // in the points' order
  std::size_t resumed = 0;           // records taken from an earlier run of the same sweep
  std::string engine;                // "4 local processes", "MPI, 8 ranks"
  double wall_time_s = 0;
  bool passed() const;  // every variant ran and passed its gates
};

// The sweep's reports, written into `dir` atomically: sweep.json, sweep.html (with the Pareto plot),
// summary.md, junit.xml (a test case per variant and gate, an error per variant that failed to run). Each
// has its own file (sweep_json.cpp, sweep_html.cpp, sweep_summary.cpp, sweep_junit.cpp).
void write_sweep_reports(const SweepResult& result, const std::filesystem::path& dir);
std::string sweep_json(const SweepResult& result);
std::string sweep_html(const SweepResult& result);
std::string sweep_summary_md(const SweepResult& result);
std::string sweep_junit_xml(const SweepResult& result);

}  // namespace beadtwin::scenarios
