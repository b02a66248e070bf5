#include "tools/mpi_module.hpp"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <map>
#include <memory>
#include <string>
#include <thread>

#include "thermal/mpi/mpi_communicator.hpp"

namespace beadtwin::tools::mpi {
namespace {

constexpr int kTagReady = 1, kTagResult = 2, kTagWork = 3, kTagStop = 4;
// How often rank 0 looks for a message while it waits.
constexpr std::chrono::milliseconds kPoll{20};

class Session {
 public:
  Session() {
    MPI_Init(nullptr, nullptr);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  ~Session() { MPI_Finalize(); }
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  int rank_ = 0, size_ = 1;
};

void send(const std::string& text, int to, int tag) {
  MPI_Send(text.data(), static_cast<int>(text.size()), MPI_CHAR, to, tag, MPI_COMM_WORLD);
}

// The next message from `from` (MPI_ANY_SOURCE: anyone), with its sender and tag. Rank 0 waits by polling
// with short sleeps rather than in MPI_Probe, which spins a core that a variant beside it needs.
std::string receive(int from, int& source, int& tag, bool sleep_while_waiting) {
  MPI_Status st;
  if (sleep_while_waiting) {
    for (int flag = 0;;) {
      MPI_Iprobe(from, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
      if (flag) break;
      std::this_thread::sleep_for(kPoll);
    }
  } else {
    MPI_Probe(from, MPI_ANY_TAG, MPI_COMM_WORLD, &st);
  }
  int count = 0;
  MPI_Get_count(&st, MPI_CHAR, &count);
  std::string text(static_cast<std::size_t>(count), '\0');
  MPI_Recv(text.data(), count, MPI_CHAR, st.MPI_SOURCE, st.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  source = st.MPI_SOURCE;
  tag = st.MPI_TAG;
  return text;
}

// How many ranks on this node run variants (all but rank 0 when `master_idles`), so each takes its share of
// the node.
int workers_on_this_node(int rank, bool master_idles = true) {
  MPI_Comm node;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank, MPI_INFO_NULL, &node);
  int size = 1, has_master = 0;
  const int is_master = rank == 0 && master_idles ? 1 : 0;
  MPI_Comm_size(node, &size);
  MPI_Allreduce(&is_master, &has_master, 1, MPI_INT, MPI_MAX, node);
  MPI_Comm_free(&node);
  return std::max(1, size - has_master);
}

// Ranks 1 and up: say ready, then run what rank 0 sends until it says stop.
void worker(const Session& s, const Callbacks& cb, int sharing) {
  char host[MPI_MAX_PROCESSOR_NAME] = {};
  int len = 0;
  MPI_Get_processor_name(host, &len);
  const std::string name =
      "rank " + std::to_string(s.rank()) + " on " + std::string(host, static_cast<std::size_t>(len));
  send("", 0, kTagReady);
  for (;;) {
    int source = 0, tag = 0;
    const std::string item = receive(0, source, tag, false);
    if (tag != kTagWork) return;
    send(cb.run(item, sharing, name), 0, kTagResult);
  }
}

// Rank 0: plans, hands the work out one item at a time as ranks come free (each first says it is ready,
// then sends each result), gathers, and reports.
int master(const Session& s, const Callbacks& cb) {
  int stopped = 0;
  const auto stop_all = [&] {
    while (stopped < s.size() - 1) {
      int source = 0, tag = 0;
      (void)receive(MPI_ANY_SOURCE, source, tag, true);
      send("", source, kTagStop);
      ++stopped;
    }
  };
  std::vector<std::string> items;
  try {
    items = cb.plan(s.size());
  } catch (...) {
    stop_all();  // bad input: the workers end, then the error reaches the command line
    throw;
  }
  // From here the workers wait on rank 0: an error (a result that cannot be kept) ends the whole job
  // rather than leave them waiting for ever.
  try {
    std::map<int, std::size_t> busy;  // rank -> item
    std::size_t next = 0;
    while (stopped < s.size() - 1) {
      int source = 0, tag = 0;
      const std::string text = receive(MPI_ANY_SOURCE, source, tag, true);
      if (tag == kTagResult) {
        const std::size_t item = busy.at(source);
        busy.erase(source);
        cb.gathered(item, text, source);
      }
      if (next < items.size()) {
        send(items[next], source, kTagWork);
        busy[source] = next++;
      } else {
        send("", source, kTagStop);
        ++stopped;
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "internal error: %s\n", e.what());
    MPI_Abort(MPI_COMM_WORLD, 3);
  }
  return cb.report();
}

}  // namespace
}  // namespace beadtwin::tools::mpi

extern "C" int beadtwin_sweep_mpi(const beadtwin::tools::mpi::Callbacks& cb) {
  using namespace beadtwin::tools::mpi;
  Session s;
  const int sharing = workers_on_this_node(s.rank());
  if (s.size() == 1) return cb.plain();
  if (s.rank() != 0) {
    worker(s, cb, sharing);
    return 0;
  }
  return master(s, cb);
}

extern "C" int beadtwin_run_mpi(const beadtwin::tools::mpi::RunJob& job) {
  using namespace beadtwin::tools::mpi;
  Session s;
  const int on_this_node = workers_on_this_node(s.rank(), false);
  std::unique_ptr<beadtwin::thermal::Communicator> ranks = beadtwin::thermal::world_communicator();
  try {
    return job.run(*ranks, on_this_node);
  } catch (...) {
    const std::exception_ptr error = std::current_exception();
    if (s.size() == 1 || job.shared_error(error)) {
      ranks.reset();
      throw;  // every rank ends alike; the session ends as the exception leaves
    }
    try {
      std::rethrow_exception(error);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "internal error on rank %d: %s\n", s.rank(), e.what());
    } catch (...) {
      std::fprintf(stderr, "internal error on rank %d\n", s.rank());
    }
    MPI_Abort(MPI_COMM_WORLD, 3);
    return 3;
  }
}
