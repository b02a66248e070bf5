// The runner: the whole pipeline for every variant of a scenario, reading like the pipeline —
// part → slice → program → deposit → thermal → render → metrics and gates — then the reports.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "scenarios/input/result.hpp"
#include "thermal/communicator.hpp"

namespace beadtwin::scenarios {

// How a run is run: where it writes, which variants, who hears of its progress, and its MPI ranks.
struct RunOptions {
  std::filesystem::path out_dir = "beadtwin-out";
  std::vector<std::string> variants;  // only these (all when empty); unknown names are an InputError
  std::function<void(const std::string&)> log;  // progress lines; empty to stay quiet
  // How far a run has got: the variant, the stage, and the stage's fraction done (0 as it starts, then
  // during the long stages, deposit and thermal); empty: no reports.
  std::function<void(const std::string& variant, const std::string& stage, double fraction)> progress;
  // Under mpirun: the ranks that share each variant's thermal solve (HeatOptions::communicator). This is rank
  // 0, which runs everything else and writes every output; the others call share_thermal. Null: alone.
  thermal::Communicator* thermal_ranks = nullptr;
};

// Runs the scenario and writes every output into options.out_dir. Throws InputError for bad input
// found late (for example an STL that cannot be read) before writing any report.
RunResult run_scenario(const Scenario& scenario, const RunOptions& options);

// A rank other than 0 of a run under mpirun (RunOptions::thermal_ranks): slices and deposits the variants as
// rank 0 does and takes its share of each thermal solve; writes nothing. Returns false when rank 0 stopped
// on bad input before any solve (it reports it).
bool share_thermal(const Scenario& scenario, const RunOptions& options);

// Slices one variant and returns its print program (for `beadtwin slice`).
std::string slice_program(const Scenario& scenario, const std::string& variant_name);

}  // namespace beadtwin::scenarios
