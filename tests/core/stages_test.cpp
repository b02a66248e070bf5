// Stages (core/stages.hpp): the stages run here and aside, recorded in one order.
#include "core/stages.hpp"

#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace beadtwin {
namespace {

TEST(Stages, RunTimesEachStageAndLogsItInOrder) {
  std::vector<std::string> lines, started;
  Stages stages([&](const std::string& l) { lines.push_back(l); },
                [&](const std::string& s) { started.push_back(s); });
  EXPECT_EQ(stages.run("one", [] { return 7; }), 7);
  stages.record("two", 1.5);
  ASSERT_EQ(stages.times().size(), 2u);
  EXPECT_EQ(stages.times()[0].name, "one");
  EXPECT_GE(stages.times()[0].seconds, 0.0);
  EXPECT_EQ(stages.times()[1].name, "two");
  EXPECT_DOUBLE_EQ(stages.times()[1].seconds, 1.5);
  EXPECT_EQ(started, std::vector<std::string>{"one"});  // a recorded stage was started elsewhere
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_NE(lines[1].find("two"), std::string::npos);
}

// Goes of a stage on other threads add up, and the stage is recorded where record_aside says, once.
TEST(Stages, GoesAsideAddUpAndAreRecordedWhereAsked) {
  std::vector<std::string> started;
  Stages stages({}, [&](const std::string& s) { started.push_back(s); });
  const auto sleep = [] { std::this_thread::sleep_for(std::chrono::milliseconds(20)); };
  std::thread other([&] { stages.run_aside("render", sleep); });
  stages.run("thermal", sleep);
  other.join();
  stages.run_aside("render", sleep, true);
  stages.record_aside("render");
  stages.record_aside("render");  // already recorded: nothing more
  stages.record_aside("skin");    // never ran: nothing
  ASSERT_EQ(stages.times().size(), 2u);
  EXPECT_EQ(stages.times()[0].name, "thermal");
  EXPECT_EQ(stages.times()[1].name, "render");
  EXPECT_GE(stages.times()[1].seconds, 0.04);                           // both goes
  EXPECT_EQ(started, (std::vector<std::string>{"thermal", "render"}));  // only the announced go
}

}  // namespace
}  // namespace beadtwin
