// `beadtwin sweep` (docs/usage.md "sweep"): runs every variant of a sweep (scenarios/sweep.hpp) and writes
// the one report. Each variant is its own `beadtwin run` process, its output in OUT/variants/NAME/, so a
// variant that fails — bad input found late, an internal error, a crash, the memory killer — is reported
// and the sweep goes on.
//
// Run plainly, up to --jobs variants run at once on this machine, each with its share of the cores. Under
// mpirun (or srun), rank 0 hands out variants one at a time to the other ranks as they come free and writes
// the report; each rank runs its variant on its node's cores. Either way a variant's record is written to
// OUT/variants/NAME/sweep.json as soon as it ends, and a sweep started again on the same output directory
// takes the records of the variants that ran with the same settings instead of running them again.
#pragma once

#include <string>
#include <vector>

namespace beadtwin::tools {

struct SweepCommand {
  std::string scenario;           // the scenario file; empty: the built-in default
  std::string base_variant;       // the scenario's variant the settings apply to; empty: the first
  std::vector<std::string> sets;  // --set KEY=V1,V2,...
  std::string combinations;       // --combinations FILE; empty: none
  std::vector<std::string> gate_exprs, gate_files;
  std::string sort;    // metric[:min|max]; empty: the Pareto x metric, else print_time_s
  std::string pareto;  // "X,Y" metrics[:min|max]; empty: no Pareto plot
  std::string out_dir = "beadtwin-sweep";
  int jobs = 0;     // variants at once on this machine; 0: one
  int threads = 0;  // threads per variant; 0: the cores over the jobs
  bool quiet = false;
};

// Runs the sweep and returns the exit code: 0 every variant ran and passed its gates, 1 a variant failed a
// gate or did not run to the end (the report says which), 2 bad input found before any variant ran (thrown
// as InputError). Under MPI every rank calls it; only rank 0 returns the sweep's code.
int run_sweep(const SweepCommand& command);

}  // namespace beadtwin::tools
