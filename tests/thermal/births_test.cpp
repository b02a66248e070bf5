// Tests of the heat solve's birth schedule (thermal/births.hpp): which cells are born together, and when.
#include "thermal/births.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/thermal/test_meshes.hpp"

namespace beadtwin::thermal {
namespace {

std::vector<ThermalCell> born_at(const std::vector<double>& times_s) {
  std::vector<ThermalCell> cells;
  for (const double t : times_s) cells.push_back(cell_at({0.0, 0.0, 0.0}, 1.0, t));
  return cells;
}

TEST(BirthSchedule, CellsWithinTheIntervalOfAGroupsFirstAreBornTogetherAtTheMiddleOfTheirTimes) {
  const std::vector<ThermalCell> cells = born_at({0.0, 0.1, 0.5, 1.0, 1.05, 5.0});
  HeatOptions options;
  options.birth_interval_s = 0.5;
  const BirthSchedule s = plan_births(cells, 10.0, options);
  EXPECT_EQ(s.interval_s, 0.5);
  EXPECT_EQ(s.automatic_interval_s, 2.0);  // a fifth of the median time constant, whether used or not
  EXPECT_TRUE(s.note.empty());
  ASSERT_EQ(s.groups.size(), 3u);
  EXPECT_EQ(s.groups[0].end, 3u);  // 0.5 is within 0.5 s of 0.0; 1.0 is not
  EXPECT_DOUBLE_EQ(s.groups[0].time_s, 0.25);
  EXPECT_EQ(s.groups[1].end, 5u);
  EXPECT_DOUBLE_EQ(s.groups[1].time_s, 1.025);
  EXPECT_EQ(s.groups[2].end, 6u);
  EXPECT_DOUBLE_EQ(s.groups[2].time_s, 5.0);
}

TEST(BirthSchedule, TheAutomaticIntervalIsAFifthOfTheMedianTimeConstant) {
  const std::vector<ThermalCell> cells = born_at({0.0, 1.0, 2.0, 3.0, 4.0, 5.0});
  const BirthSchedule s = plan_births(cells, 5.0, HeatOptions{});
  EXPECT_EQ(s.interval_s, 1.0);
  EXPECT_TRUE(s.note.empty());
  ASSERT_EQ(s.groups.size(), 3u);  // {0, 1}, {2, 3}, {4, 5}
  EXPECT_EQ(s.groups[0].end, 2u);
  EXPECT_DOUBLE_EQ(s.groups[1].time_s, 2.5);
}

TEST(BirthSchedule, TheAutomaticIntervalIsMadeLongerWhenThePrintWouldNeedTooManyEvents) {
  std::vector<double> times;
  for (int i = 0; i < 100; ++i) times.push_back(i);  // one cell a second for 99 s
  const std::vector<ThermalCell> cells = born_at(times);
  HeatOptions options;
  options.max_automatic_birth_events = 10;
  const BirthSchedule s = plan_births(cells, 5.0, options);
  EXPECT_EQ(s.automatic_interval_s, 1.0);
  EXPECT_DOUBLE_EQ(s.interval_s, 9.9);  // the span over the most events
  EXPECT_LE(s.groups.size(), 10u);
  EXPECT_EQ(s.groups.back().end, 100u);
  EXPECT_NE(s.note.find("thermal birth interval 9.9 s instead of 1 s"), std::string::npos) << s.note;
  EXPECT_NE(s.note.find("at most about 10 events"), std::string::npos) << s.note;
  // An interval asked for is kept, however many events it makes.
  options.birth_interval_s = 0.5;
  const BirthSchedule asked = plan_births(cells, 5.0, options);
  EXPECT_EQ(asked.interval_s, 0.5);
  EXPECT_EQ(asked.groups.size(), 100u);
  EXPECT_TRUE(asked.note.empty());
}

}  // namespace
}  // namespace beadtwin::thermal
