#include "core/bead.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "core/units.hpp"

namespace beadtwin {
namespace {

TEST(Bead, StadiumAreaOfARoundBeadIsTheCircle) {
  // A bead as tall as it is wide is a circle: A = π d² / 4.
  EXPECT_NEAR(bead_area_mm2(10.0, 10.0), kPi * 25.0, 1e-12);
}

TEST(Bead, WidthIsTheInverseOfArea) {
  for (double h : {0.2, 1.0, 5.08}) {
    for (double w : {h, 2 * h, 21.082}) {
      if (w < h) continue;
      EXPECT_NEAR(bead_width_mm(bead_area_mm2(w, h), h), w, 1e-12) << "w=" << w << " h=" << h;
    }
  }
}

TEST(Bead, PatentRoundBeadFlattenedToTwoTenths) {
  // Check of the patent's numbers: a 0.5 in round bead (A = 0.196 in²) flattened by the
  // roller to 0.20 in is about 1.02 in wide (conserving A, not the nozzle shape).
  const double d = 0.5 * kMmPerInch;
  const double area = kPi * d * d / 4;
  const double w = bead_width_mm(area, 0.20 * kMmPerInch);
  EXPECT_NEAR(w / kMmPerInch, 1.02, 0.01);
  // The patent's flattened bead, 0.83 in x 0.20 in, has a smaller area than the nozzle: draw-down.
  EXPECT_NEAR(bead_area_mm2(0.83 * kMmPerInch, 0.2 * kMmPerInch) / (kMmPerInch * kMmPerInch), 0.157, 0.001);
}

}  // namespace
}  // namespace beadtwin
