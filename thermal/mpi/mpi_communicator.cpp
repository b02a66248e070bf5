#include "thermal/mpi/mpi_communicator.hpp"

#include <mpi.h>

#include <numeric>
#include <vector>

#include <nvector/nvector_parallel.h>

#include "core/error.hpp"

namespace beadtwin::thermal {
namespace {

std::vector<int> displacements(std::span<const int> counts) {
  std::vector<int> d(counts.size(), 0);
  if (!counts.empty()) std::exclusive_scan(counts.begin(), counts.end(), d.begin(), 0);
  return d;
}

void check(int code, const char* call) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  throw InternalError(std::string("MPI: ") + call +
                      " failed: " + std::string(text, static_cast<std::size_t>(length)));
}

class WorldCommunicator final : public Communicator {
 public:
  WorldCommunicator() {
    // A communicator of its own, so that the solve's messages never meet anyone else's.
    check(MPI_Comm_dup(MPI_COMM_WORLD, &comm_), "MPI_Comm_dup");
    check(MPI_Comm_rank(comm_, &rank_), "MPI_Comm_rank");
    check(MPI_Comm_size(comm_, &size_), "MPI_Comm_size");
  }
  ~WorldCommunicator() override { MPI_Comm_free(&comm_); }
  WorldCommunicator(const WorldCommunicator&) = delete;
  WorldCommunicator& operator=(const WorldCommunicator&) = delete;

  int rank() const override { return rank_; }
  int size() const override { return size_; }

  void all_gather(std::span<const double> mine, std::span<const int> counts, std::span<double> all) override {
    BT_CHECK_OP(counts.size(), ==, static_cast<std::size_t>(size_));
    BT_CHECK_OP(static_cast<std::size_t>(counts[static_cast<std::size_t>(rank_)]), ==, mine.size());
    const std::vector<int> at = displacements(counts);
    check(MPI_Allgatherv(mine.data(), static_cast<int>(mine.size()), MPI_DOUBLE, all.data(), counts.data(),
                         at.data(), MPI_DOUBLE, comm_),
          "MPI_Allgatherv");
  }

  void exchange(std::span<const double> send, std::span<const int> send_counts, std::span<double> recv,
                std::span<const int> recv_counts) override {
    BT_CHECK_OP(send_counts.size(), ==, static_cast<std::size_t>(size_));
    BT_CHECK_OP(recv_counts.size(), ==, static_cast<std::size_t>(size_));
    const std::vector<int> send_at = displacements(send_counts), recv_at = displacements(recv_counts);
    check(MPI_Alltoallv(send.data(), send_counts.data(), send_at.data(), MPI_DOUBLE, recv.data(),
                        recv_counts.data(), recv_at.data(), MPI_DOUBLE, comm_),
          "MPI_Alltoallv");
  }

  N_Vector new_vector(std::size_t local_length, std::size_t global_length, SUNContext context) override {
    N_Vector v = N_VNew_Parallel(comm_, static_cast<sunindextype>(local_length),
                                 static_cast<sunindextype>(global_length), context);
    // The fused operations, and the all-reduce that thermal/vector_ops.hpp adds its blocked sums with.
    if (v != nullptr && (N_VEnableFusedOps_Parallel(v, SUNTRUE) != 0 ||
                         N_VEnableDotProdMultiLocal_Parallel(v, SUNTRUE) != 0)) {
      N_VDestroy(v);
      return nullptr;
    }
    return v;
  }

 private:
  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0, size_ = 1;
};

}  // namespace

std::unique_ptr<Communicator> world_communicator() {
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (!initialised) throw InternalError("world_communicator: MPI is not initialised");
  return std::make_unique<WorldCommunicator>();
}

}  // namespace beadtwin::thermal
