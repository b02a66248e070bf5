#include "core/flow.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "core/bead.hpp"
#include "core/error.hpp"
#include "core/units.hpp"

namespace beadtwin {
namespace {

double relative_error(double a, double b) {
  return std::abs(a - b) / std::max(std::abs(a), std::abs(b));
}

Extruder gear_pump(double cm3_per_rev) {
  Extruder e;
  e.kind = ExtruderKind::kGearPump;
  e.displacement_mm3_per_rev = cm3_per_rev * 1000.0;
  return e;
}

Extruder filament(double diameter_mm) {
  Extruder e;
  e.kind = ExtruderKind::kFilament;
  e.filament_diameter_mm = diameter_mm;
  return e;
}

TEST(Flow, BeadToRpmAndBackIsTheSameBead) {
  const Extruder pump = gear_pump(10.0);
  for (double h : {1.0, 5.08, 8.0}) {
    for (double w : {h, 2.5 * h, 21.082}) {
      if (w < h) continue;
      for (double v : {10.0, 63.5, 200.0}) {
        const double rpm = rpm_for_flow(pump, bead_flow_mm3_s(w, h, v));
        const double back = bead_width_mm(flow_for_rpm(pump, rpm) / v, h);
        EXPECT_LT(relative_error(back, w), 1e-12) << "w=" << w << " h=" << h << " v=" << v;
      }
    }
  }
}

TEST(Flow, BeadToFilamentAndBackIsTheSameBead) {
  const Extruder f = filament(2.85);
  for (double h : {0.2, 0.6, 2.0}) {
    for (double w : {h, 1.7 * h, 4.0}) {
      if (w < h) continue;
      const double e = e_per_mm(f, w, h);
      EXPECT_LT(relative_error(bead_width_for_e_per_mm(f, e, h), w), 1e-12) << "w=" << w << " h=" << h;
      // Eq. 1 and its inverse.
      EXPECT_LT(relative_error(flow_for_filament_feed(f, filament_feed_mm_s(f, 123.0)), 123.0), 1e-12);
    }
  }
}

TEST(Flow, FilamentPerMmIsEquationThree) {
  // Eq. 3 written out: v_e = 4 h (π h / 4 + b_p) / (π d_f²) · v_x, with the central rectangle b_p = w − h.
  const double d_f = 1.75;
  const Extruder f = filament(d_f);
  for (double h : {0.2, 0.4}) {
    for (double w : {0.45, 0.8}) {
      const double b_p = w - h;
      const double v_x = 40.0;
      const double v_e = 4.0 * h * (kPi / 4.0 * h + b_p) / (kPi * d_f * d_f) * v_x;
      EXPECT_LT(relative_error(e_per_mm(f, w, h) * v_x, v_e), 1e-12);
      EXPECT_LT(relative_error(filament_feed_mm_s(f, bead_flow_mm3_s(w, h, v_x)), v_e), 1e-12);
    }
  }
}

TEST(Flow, PatentBeadByHand) {
  // US 12,390,995: the 0.83 in x 0.20 in bead, laid here at 2.5 in/s. By hand, in inches:
  // A = 0.20 (0.83 − 0.20) + π 0.20² / 4 = 0.126 + 0.0314159 = 0.1574159 in², Q = 2.5 A = 0.3935398 in³/s,
  // which is 0.3935398 · 16387.064 = 6448.96 mm³/s; a 10 cm³/rev pump turns 60 · 6448.96 / 10000 = 38.69 rpm.
  const double q = bead_flow_mm3_s(0.83 * kMmPerInch, 0.20 * kMmPerInch, 2.5 * kMmPerInch);
  const double in3 = kMmPerInch * kMmPerInch * kMmPerInch;
  EXPECT_LT(relative_error(q / in3, (0.20 * (0.83 - 0.20) + kPi * 0.20 * 0.20 / 4.0) * 2.5), 1e-12);
  EXPECT_NEAR(q, 6448.96, 0.01);
  EXPECT_NEAR(rpm_for_flow(gear_pump(10.0), q), 38.69, 0.005);
  // A screw of the same displacement turns at the same speed.
  Extruder screw = gear_pump(10.0);
  screw.kind = ExtruderKind::kScrew;
  EXPECT_EQ(rpm_for_flow(screw, q), rpm_for_flow(gear_pump(10.0), q));
}

TEST(Flow, ConstantFeedOnARisingLayerSlowsTheHead) {
  // Eq. 12: constant filament feed v_e, height h = h0 + m x, central rectangle b_p: the speed falls as the
  // height grows and the flow stays π d_f² v_e / 4 (eqs. 9 and 10).
  const double d_f = 1.75, v_e = 4.0, b_p = 0.3, h0 = 0.2, m = 0.002;
  const Extruder f = filament(d_f);
  const double q = kPi * d_f * d_f / 4.0 * v_e;
  double previous = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= 100; ++i) {
    const double x = i * 2.0;
    const double h = h0 + m * x;
    const double v_x = speed_for_height(f, v_e, b_p, h);
    const double paper = kPi * d_f * d_f / (4.0 * h * (kPi / 4.0 * h + b_p)) * v_e;
    EXPECT_LT(relative_error(v_x, paper), 1e-12) << "x=" << x;
    EXPECT_LT(relative_error((kPi / 4.0 * h * h + b_p * h) * v_x, q), 1e-12) << "x=" << x;
    EXPECT_LT(v_x, previous) << "x=" << x;
    previous = v_x;
    // The same speed from the flow.
    EXPECT_LT(relative_error(speed_for_height(q, b_p, h), v_x), 1e-12);
  }
  // Over the ramp the height doubles and more: the head slows by more than half.
  EXPECT_LT(speed_for_height(f, v_e, b_p, h0 + m * 200.0), 0.5 * speed_for_height(f, v_e, b_p, h0));
}

TEST(Flow, ExcessIsReportedNotClipped) {
  Extruder pump = gear_pump(10.0);
  pump.max_flow_mm3_s = 5000.0;
  pump.max_rpm = 40.0;
  // 6449 mm³/s: 1.29 times the flow limit, 0.967 of the speed limit.
  FlowExcess x = flow_excess(pump, 6448.96);
  EXPECT_TRUE(x.exceeded());
  EXPECT_NEAR(x.ratio, 6448.96 / 5000.0, 1e-12);
  EXPECT_EQ(x.limit, "max_flow");
  EXPECT_NEAR(x.rpm, 38.69, 0.005);
  pump.max_rpm = 20.0;
  x = flow_excess(pump, 6448.96);
  EXPECT_EQ(x.limit, "max_rpm");
  EXPECT_NEAR(x.ratio, x.rpm / 20.0, 1e-12);
  EXPECT_FALSE(flow_excess(pump, 500.0).exceeded());
  EXPECT_EQ(flow_excess(gear_pump(10.0), 1e9).ratio, 0.0) << "no limits, nothing exceeded";

  // Over a toolpath: the worst move, by its commanded flow; the coast is left out.
  Toolpath tp;
  const auto add = [&](MoveKind kind, Feature feature, double length, double feed, double volume,
                       double duration) {
    Move m;
    m.kind = kind;
    m.feature = feature;
    m.end = {length, 0, 0};
    m.feed_mm_s = feed;
    m.volume_mm3 = volume;
    m.duration_s = duration;
    tp.moves.push_back(m);
  };
  add(MoveKind::kPrint, Feature::kBoundary, 100, 50, 100 * 80, 0);  // 4000 mm³/s
  add(MoveKind::kDwell, Feature::kPrime, 0, 0, 9000, 2);            // 4500 mm³/s
  add(MoveKind::kPrint, Feature::kCoast, 10, 50, 10 * 200, 0);      // 10000 mm³/s, pump off
  add(MoveKind::kTravel, Feature::kTravel, 100, 500, 0, 0);
  pump.max_rpm = 0.0;
  const FlowExcess worst = worst_flow_excess(pump, tp);
  EXPECT_EQ(worst.move, 1);
  EXPECT_NEAR(worst.flow_mm3_s, 4500.0, 1e-9);
  EXPECT_FALSE(worst.exceeded());
  pump.max_flow_mm3_s = 4200.0;
  EXPECT_TRUE(worst_flow_excess(pump, tp).exceeded());
}

TEST(Flow, ExtruderProblemsAreInputErrors) {
  EXPECT_NO_THROW(validate(gear_pump(10.0)));
  EXPECT_NO_THROW(validate(filament(1.75)));
  Extruder bad = gear_pump(0.0);
  bad.max_rpm = -1.0;
  try {
    validate(bad);
    FAIL() << "a pump without a displacement was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "extruder");
    EXPECT_NE(e.message().find("displacement"), std::string::npos) << e.message();
    EXPECT_NE(e.message().find("max RPM"), std::string::npos) << "every problem: " << e.message();
  }
  EXPECT_THROW(validate(filament(0.0)), InputError);
  EXPECT_THROW(rpm_for_flow(filament(1.75), 10.0), InternalError)
      << "a filament drive without a displacement";
}

}  // namespace
}  // namespace beadtwin
