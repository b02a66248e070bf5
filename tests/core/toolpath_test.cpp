#include "core/toolpath.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace beadtwin {
namespace {

Move straight(double x0, double x1, double feed, MoveKind kind = MoveKind::kPrint) {
  Move m;
  m.start = {x0, 0, 1};
  m.end = {x1, 0, 1};
  m.kind = kind;
  m.feed_mm_s = feed;
  m.layer = 0;
  return m;
}

TEST(Motion, TrapezoidMatchesTheAnalyticTime) {
  // From rest to rest over L with cruise v and acceleration a: t = L/v + v/a when L >= v²/a.
  Toolpath tp;
  tp.layers.resize(1);
  tp.moves.push_back(straight(0, 1000, 100));
  MotionLimits lim;
  lim.max_feed_mm_s = 1000;
  lim.acceleration_mm_s2 = 500;
  time_toolpath(tp, lim);
  EXPECT_NEAR(tp.moves[0].duration_s, 1000.0 / 100 + 100.0 / 500, 1e-9);
}

TEST(Motion, ShortMoveIsATriangle) {
  // Too short to reach cruise: t = 2 sqrt(L/a).
  Toolpath tp;
  tp.layers.resize(1);
  tp.moves.push_back(straight(0, 10, 1000));
  MotionLimits lim;
  lim.max_feed_mm_s = 1000;
  lim.acceleration_mm_s2 = 1000;
  time_toolpath(tp, lim);
  EXPECT_NEAR(tp.moves[0].duration_s, 2 * std::sqrt(10.0 / 1000), 1e-9);
}

TEST(Motion, StraightContinuationKeepsSpeedAndCornersSlowDown) {
  MotionLimits lim;
  lim.max_feed_mm_s = 1000;
  lim.acceleration_mm_s2 = 1000;
  lim.junction_deviation_mm = 0.05;
  Toolpath straight_on;
  straight_on.layers.resize(1);
  straight_on.moves = {straight(0, 500, 100), straight(500, 1000, 100)};
  time_toolpath(straight_on, lim);
  // Two collinear halves take as long as the whole line.
  EXPECT_NEAR(straight_on.total_time_s(), 1000.0 / 100 + 100.0 / 1000, 1e-9);

  Toolpath corner = straight_on;
  corner.moves[1].start = {500, 0, 1};
  corner.moves[1].end = {500, 500, 1};
  time_toolpath(corner, lim);
  EXPECT_GT(corner.total_time_s(), straight_on.total_time_s() + 0.05);
  EXPECT_EQ(corner.layers[0].start_s, 0.0);
  EXPECT_NEAR(corner.layers[0].end_s, corner.total_time_s(), 1e-12);
}

TEST(Motion, HeadMovesOnThroughTheMeltOffIntoACoast) {
  // Melt off (an instantaneous event) between a print move and its coast: the head does not stop, so the
  // pair takes as long as one straight move. Before anything but a coast the event still stops the head.
  MotionLimits lim;
  lim.max_feed_mm_s = 1000;
  lim.acceleration_mm_s2 = 1000;
  Move off;
  off.kind = MoveKind::kDwell;
  off.event = ExtruderEvent::kMeltOff;
  off.start = off.end = {500, 0, 1};
  off.layer = 0;
  Move coast = straight(500, 1000, 100);
  coast.feature = Feature::kCoast;
  Toolpath tp;
  tp.layers.resize(1);
  tp.moves = {straight(0, 500, 100), off, coast};
  time_toolpath(tp, lim);
  EXPECT_NEAR(tp.total_time_s(), 1000.0 / 100 + 100.0 / 1000, 1e-9);
  tp.moves[2].feature = Feature::kBoundary;
  time_toolpath(tp, lim);
  EXPECT_NEAR(tp.total_time_s(), 2 * (500.0 / 100 + 100.0 / 1000), 1e-9);
}

TEST(Motion, DwellKeepsItsDuration) {
  Toolpath tp;
  tp.layers.resize(1);
  Move d;
  d.kind = MoveKind::kDwell;
  d.duration_s = 2.5;
  d.layer = 0;
  tp.moves = {straight(0, 100, 50), d};
  time_toolpath(tp, {});
  EXPECT_DOUBLE_EQ(tp.moves[1].duration_s, 2.5);
  EXPECT_NEAR(tp.moves[1].start_s, tp.moves[0].duration_s, 1e-12);
}

TEST(Motion, TimeWithoutTimingIsTheTimedTotal) {
  // motion_time_s gives the total time_toolpath finds, to the bit, and leaves the toolpath untimed.
  MotionLimits lim;
  lim.max_feed_mm_s = 1000;
  lim.acceleration_mm_s2 = 1000;
  lim.junction_deviation_mm = 0.05;
  Move dwell;
  dwell.kind = MoveKind::kDwell;
  dwell.duration_s = 1.5;
  dwell.start = dwell.end = {500, 500, 1};
  dwell.layer = 0;
  Toolpath tp;
  tp.layers.resize(1);
  tp.moves = {straight(0, 500, 100), straight(500, 0, 80, MoveKind::kTravel), straight(0, 500, 120)};
  tp.moves[2].end = {500, 500, 1};
  tp.moves.push_back(dwell);
  const double t = motion_time_s(tp, lim);
  for (const Move& m : tp.moves) EXPECT_EQ(m.start_s, 0.0);
  EXPECT_EQ(tp.moves[0].duration_s, 0.0);
  time_toolpath(tp, lim);
  EXPECT_EQ(t, tp.total_time_s());
  EXPECT_GT(t, 1.5);
  EXPECT_EQ(motion_time_s(Toolpath{}, lim), 0.0);
}

TEST(Toolpath, LayersMustBeContiguous) {
  Toolpath tp;
  tp.layers.resize(2);
  tp.moves = {straight(0, 1, 1), straight(1, 2, 1), straight(2, 3, 1)};
  tp.moves[1].layer = 1;
  EXPECT_THROW(tp.index_layers(), InternalError);
}

TEST(AtomicFile, WritesWholeFileAndLeavesNoTemporary) {
  const auto dir = std::filesystem::temp_directory_path() / "beadtwin_atomic_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  write_file_atomic(dir / "a.txt", "hello");
  std::ifstream f(dir / "a.txt");
  std::string s;
  std::getline(f, s);
  EXPECT_EQ(s, "hello");
  int files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1);
  {
    AtomicPath never(dir / "b.txt");
    std::ofstream(never.temp()) << "half";
  }  // not committed: gone
  EXPECT_FALSE(std::filesystem::exists(dir / "b.txt"));
  files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1);
  std::filesystem::remove_all(dir);
}

TEST(Errors, InputErrorNamesFileLineAndKey) {
  const InputError e({"part.yaml", 12, 5}, "sections.walls.speed", "expected a speed");
  EXPECT_STREQ(e.what(), "part.yaml:12:5: sections.walls.speed: expected a speed");
  const InputError bare({"", 3, 0}, "", "oops");
  EXPECT_STREQ(bare.what(), "line 3: oops");
}

}  // namespace
}  // namespace beadtwin
