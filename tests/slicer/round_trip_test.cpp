// Every writer's program read back gives the planned Toolpath: positions within the
// program's last decimal, material within 0.1 %, the same beads, and the same times once the read program
// is timed by the same motion model.
#include <cmath>
#include <sstream>

#include <gtest/gtest.h>

#include "core/flow.hpp"
#include "gcode/program_reader.hpp"
#include "gcode/writer.hpp"
#include "slicer/mesh.hpp"
#include "slicer/plan.hpp"

namespace beadtwin::slicer {
namespace {

// A small two-section part, sliced with boundary passes and a smart-zigzag fill.
Toolpath planned(const MotionLimits& motion, double w, double h) {
  SectionParams s;
  s.name = "plate";
  s.z_max_mm = 4 * h;
  s.layer_height_mm = h;
  s.bead_width_mm = w;
  s.print_speed_mm_s = 40;
  s.travel_speed_mm_s = 150;
  s.boundary.passes = 2;
  s.fill.enabled = true;
  return plan_toolpath(make_box({60 * w, 40 * w, 4 * h}), {s}, motion);
}

int beads(const Toolpath& tp) {
  int n = 0;
  for (const Move& m : tp.moves) n += m.event == ExtruderEvent::kMeltOn;
  return n;
}

// `time_tol` is relative: a program without melt codes (Marlin) reads back without the melt-on and melt-off
// stops between beads, so the head carries its speed from one bead into the next travel.
void expect_round_trip(const Toolpath& want, const gcode::GcodeDialect& dialect, const Extruder* extruder,
                       const MotionLimits& motion, double position_tol_mm, double time_tol = 1e-3,
                       double volume_tol = 1e-3) {
  gcode::GcodeOptions o;
  o.extruder = extruder;
  std::istringstream in(gcode::write_gcode(want, dialect, {}, o));
  gcode::ReadStats stats;
  Toolpath got = gcode::read_gcode(in, "round-trip.nc", gcode::reader_options_for(dialect, extruder), &stats);
  time_toolpath(got, motion);
  EXPECT_EQ(stats.warning_count(), 0u) << (stats.messages.empty() ? "" : stats.messages.front());
  ASSERT_EQ(got.layers.size(), want.layers.size());
  if (!dialect.melt_on.empty()) {
    EXPECT_EQ(beads(got), beads(want));
  }
  EXPECT_NEAR(got.commanded_volume_mm3(), want.commanded_volume_mm3(),
              volume_tol * want.commanded_volume_mm3());
  EXPECT_NEAR(got.print_length_mm(), want.print_length_mm(), 1e-3 * want.print_length_mm());
  EXPECT_NEAR(got.total_time_s(), want.total_time_s(), time_tol * want.total_time_s());
  // The deposits, one by one, in order: same ends, same material.
  std::vector<const Move*> a, b;
  for (const Move& m : want.moves)
    if (m.deposits()) a.push_back(&m);
  for (const Move& m : got.moves)
    if (m.deposits()) b.push_back(&m);
  ASSERT_EQ(b.size(), a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_LT((b[i]->end - a[i]->end).norm(), position_tol_mm) << i;
    EXPECT_NEAR(b[i]->volume_mm3, a[i]->volume_mm3, volume_tol * a[i]->volume_mm3 + 1e-9) << i;
  }
}

TEST(RoundTrip, GantryProgramWithPumpSpeedsInInches) {
  MotionLimits motion;
  const Toolpath tp = planned(motion, 20, 5);
  Extruder pump;
  pump.displacement_mm3_per_rev = 10000;
  gcode::GcodeDialect d;
  d.inches = true;
  d.decimals = 4;
  expect_round_trip(tp, d, &pump, motion, 0.5 * 25.4e-4 * std::sqrt(3.0) + 1e-9);
}

TEST(RoundTrip, MarlinProgramsWithRelativeAndAbsoluteE) {
  MotionLimits motion;
  motion.max_feed_mm_s = 200;
  motion.acceleration_mm_s2 = 1500;
  const Toolpath tp = planned(motion, 0.45, 0.2);
  Extruder filament;
  filament.kind = ExtruderKind::kFilament;
  filament.filament_diameter_mm = 1.75;
  gcode::GcodeDialect d;
  d.melt_on.clear();
  d.melt_off.clear();
  d.decimals = 5;
  expect_round_trip(tp, d, &filament, motion, 1e-5 * std::sqrt(3.0), 0.01);
  d.absolute_e = true;
  expect_round_trip(tp, d, &filament, motion, 1e-5 * std::sqrt(3.0), 0.01);
}

TEST(RoundTrip, FanucMacroProgramWithLoopedLayers) {
  MotionLimits motion;
  SectionParams s;
  s.name = "ring";
  s.z_max_mm = 30;
  s.layer_height_mm = 5;
  s.bead_width_mm = 20;
  s.print_speed_mm_s = 60;
  s.travel_speed_mm_s = 300;
  s.outline_path = {{0, 0}, {400, 0}, {400, 300}, {0, 300}};
  const Toolpath tp = plan_toolpath(TriangleMesh{}, {s}, motion);
  Extruder pump;
  pump.displacement_mm3_per_rev = 10000;
  gcode::GcodeDialect d;
  d.macro_loops = true;
  // The pump's speed word has one decimal (S34.6): material within 0.2 %.
  expect_round_trip(tp, d, &pump, motion, 1e-3, 1e-3, 2e-3);
}

}  // namespace
}  // namespace beadtwin::slicer
