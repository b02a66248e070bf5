// The MPI half of beadtwin, a module of its own (libbeadtwin_mpi.so), loaded only when beadtwin is launched
// by mpirun or srun:
// - `beadtwin sweep` (tools/sweep_runner.hpp): the messages between rank 0, which hands the variants out and
//   writes the report, and the other ranks, which run them;
// - `beadtwin run`: every rank takes its share of each variant's thermal solve (thermal/communicator.hpp).
//
// Why a module: Open MPI brings eight shared libraries more, which the dynamic loader would bind at every
// start of beadtwin, for every command, most of which never meet MPI (docs/PERFORMANCE.md measures the
// cost). The module
// knows nothing of scenarios: the work comes to it through the callbacks below.
#pragma once

#include <cstddef>
#include <exception>
#include <functional>
#include <string>
#include <vector>

namespace beadtwin::thermal {
class Communicator;
}

namespace beadtwin::tools::mpi {

// What the protocol asks of the sweep, each on the rank its comment names.
struct Callbacks {
  // Rank 0, first: checks the inputs and prepares the output folder (throws InputError on bad input, after
  // which the workers are told to stop); returns the work to hand out, one text per variant still to run.
  // `ranks` is the number of ranks, rank 0 included.
  std::function<std::vector<std::string>(int ranks)> plan;
  // Rank 0: the result a worker (`rank`) sent for work item `item`.
  std::function<void(std::size_t item, const std::string& result, int rank)> gathered;
  // Rank 0, last: writes the report; returns the sweep's exit code.
  std::function<int()> report;
  // Ranks 1 and up: runs one work item and returns its result. `sharing` is the number of ranks on this
  // node that run variants (they share its cores and memory); `worker` names the rank and its host.
  std::function<std::string(const std::string& item, int sharing, const std::string& worker)> run;
  // A single rank (mpirun -n 1): the plain sweep.
  std::function<int()> plain;
};

// The sweep's entry point: this rank's part of the sweep, and its exit code (rank 0's is the sweep's).
using Entry = int (*)(const Callbacks&);
constexpr const char* kEntryName = "beadtwin_sweep_mpi";

// A run whose thermal solves the ranks share.
struct RunJob {
  // Every rank: its part of the run, given the job's ranks and how many of them are on this node (they
  // share its cores); returns the rank's exit code.
  std::function<int(thermal::Communicator& ranks, int on_this_node)> run;
  // Whether an error is one every rank meets alike (bad input, found the same way on each): each rank then
  // ends with it. Any other ends the whole job (MPI_Abort), as the other ranks may be waiting for this one.
  std::function<bool(std::exception_ptr)> shared_error;
};
using RunEntry = int (*)(const RunJob&);
constexpr const char* kRunEntryName = "beadtwin_run_mpi";

// The module's file name; beadtwin looks for it beside itself, then where the build put it.
constexpr const char* kModuleName = "libbeadtwin_mpi.so";

}  // namespace beadtwin::tools::mpi
