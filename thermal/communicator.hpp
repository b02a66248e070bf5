// The ranks of an MPI job as the thermal solve sees them, when one part's heat transfer is shared among them
// (HeatOptions::communicator, thermal/heat.hpp).
//
// The thermal library does not link MPI: beadtwin would then load Open MPI's libraries at every start, for
// every command (tools/mpi_module.hpp measures it). The MPI implementation of this interface lives in
// thermal/mpi/ and is linked only into what runs under mpirun: the MPI module and its tests.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include <sundials/sundials_context.h>
#include <sundials/sundials_nvector.h>

namespace beadtwin::thermal {

// The ranks' collective operations the solve needs.
class Communicator {
 public:
  virtual ~Communicator() = default;
  virtual int rank() const = 0;  // this process's rank, 0..size() − 1
  virtual int size() const = 0;  // how many ranks there are
  // Every rank's `mine` concatenated in rank order into `all` (MPI_Allgatherv): counts[r] values from rank r.
  virtual void all_gather(std::span<const double> mine, std::span<const int> counts,
                          std::span<double> all) = 0;
  // Sends send_counts[r] values of `send` (in rank order) to each rank r and receives recv_counts[r] values
  // from each into `recv` (MPI_Alltoallv).
  virtual void exchange(std::span<const double> send, std::span<const int> send_counts,
                        std::span<double> recv, std::span<const int> recv_counts) = 0;
  // A SUNDIALS MPI-parallel vector (N_VNew_Parallel) on these ranks: `local_length` of its `global_length`
  // values on this rank, with the fused operations enabled. Null when SUNDIALS fails.
  virtual N_Vector new_vector(std::size_t local_length, std::size_t global_length, SUNContext context) = 0;

  // One value from each rank, in rank order (on every rank).
  std::vector<double> gather_each(double value) {
    const std::vector<int> one_each(static_cast<std::size_t>(size()), 1);
    std::vector<double> all(one_each.size());
    all_gather({&value, 1}, one_each, all);
    return all;
  }
};

}  // namespace beadtwin::thermal
