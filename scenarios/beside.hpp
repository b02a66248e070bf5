// How the runner runs work beside a stage that keeps only part of the machine busy (the deposit, the
// thermal stage's serial integrator steps): one helper for a thread beside the caller's, one for a thread
// given a single core of TBB's pool, and a list of jobs each done once by whichever thread comes to it first.
// Whether there is room in memory for the work beside is the caller's decision (RunMemory).
#pragma once

#include <atomic>
#include <deque>
#include <functional>
#include <future>
#include <type_traits>
#include <utility>

#include <tbb/task_arena.h>

namespace beadtwin::scenarios {

// Runs `main` on the calling thread and `side` on a thread of its own beside it; returns main's result once
// both are done. An error of `main` is thrown once `side` has finished too; an error of `side` after `main`
// has finished.
template <class Main, class Side>
auto beside(Main&& main, Side&& side) {
  std::future<void> other = std::async(std::launch::async, std::forward<Side>(side));
  if constexpr (std::is_void_v<std::invoke_result_t<Main>>) {
    main();  // on an error, `other`'s destructor waits for `side`
    other.get();
  } else {
    auto result = main();
    other.get();
    return result;
  }
}

// Starts `work` on a thread of its own with one core of TBB's pool, for work beside a stage that keeps the
// others busy. Its result, or its error, comes from the future; the future waits for it as it is destroyed.
template <class F>
auto on_one_core(F&& work) {
  return std::async(std::launch::async, [work = std::forward<F>(work)]() mutable {
    tbb::task_arena one_core(1);
    return one_core.execute(work);
  });
}

// Jobs each done once, by whichever thread calls work() first after it was added. Add every job before any
// thread works: adding is not thread-safe, working is.
class SharedJobs {
 public:
  void add(std::function<void()> job) { jobs_.emplace_back().work = std::move(job); }
  // Does every job not yet taken, in the order they were added, on the calling thread.
  void work() {
    for (Job& job : jobs_)
      if (!job.taken.test_and_set()) job.work();
  }

 private:
  struct Job {
    std::atomic_flag taken;
    std::function<void()> work;
  };
  std::deque<Job> jobs_;  // a deque: a job never moves once added
};

}  // namespace beadtwin::scenarios
