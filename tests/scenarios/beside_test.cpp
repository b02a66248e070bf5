// The runner's concurrency helper (scenarios/beside.hpp).
#include "scenarios/beside.hpp"

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace beadtwin::scenarios {
namespace {

TEST(Beside, RunsBothAndReturnsMainsResultOnceBothAreDone) {
  std::atomic<bool> side_done = false;
  std::thread::id side_thread;
  const int r = beside([] { return 42; },
                       [&] {
                         std::this_thread::sleep_for(std::chrono::milliseconds(30));
                         side_thread = std::this_thread::get_id();
                         side_done = true;
                       });
  EXPECT_EQ(r, 42);
  EXPECT_TRUE(side_done);
  EXPECT_NE(side_thread, std::this_thread::get_id());
}

TEST(Beside, AnErrorOfEitherIsThrownAfterBothHaveFinished) {
  std::atomic<bool> side_done = false;
  EXPECT_THROW(beside([]() -> int { throw std::runtime_error("main"); },
                      [&] {
                        std::this_thread::sleep_for(std::chrono::milliseconds(30));
                        side_done = true;
                      }),
               std::runtime_error);
  EXPECT_TRUE(side_done);
  bool main_done = false;
  EXPECT_THROW(beside([&] { return main_done = true; }, [] { throw std::logic_error("side"); }),
               std::logic_error);
  EXPECT_TRUE(main_done);
}

TEST(SharedJobs, EachJobIsDoneOnceByWhicheverThreadComesFirst) {
  SharedJobs jobs;
  std::vector<std::atomic<int>> runs(50);
  for (auto& r : runs) jobs.add([&r] { ++r; });
  std::thread a([&] { jobs.work(); });
  jobs.work();
  a.join();
  jobs.work();  // all taken: nothing
  for (const auto& r : runs) EXPECT_EQ(r.load(), 1);
}

TEST(OnOneCore, RunsTheWorkWithOneCoreOfThePool) {
  auto f = on_one_core([] { return tbb::this_task_arena::max_concurrency(); });
  EXPECT_EQ(f.get(), 1);
}

}  // namespace
}  // namespace beadtwin::scenarios
