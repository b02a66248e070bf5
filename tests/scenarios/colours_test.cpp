// The colours the runner paints on the part.
#include "scenarios/colours.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace beadtwin::scenarios {
namespace {

// The deviation map: white at the white point, the scale symmetric about it, saturated beyond it.
TEST(Colours, DeviationMapIsDivergingAndSymmetric) {
  const double white = 2.0, half = 5.0;
  EXPECT_EQ(hex(deviation_colour(white, white, half)), "#f7f7f7");
  EXPECT_EQ(hex(deviation_colour(white - half, white, half)), "#0571b0");  // short: blue
  EXPECT_EQ(hex(deviation_colour(white + half, white, half)), "#ca0020");  // over: red
  EXPECT_EQ(hex(deviation_colour(white - 10 * half, white, half)), "#0571b0");
  EXPECT_EQ(hex(deviation_colour(white + 10 * half, white, half)), "#ca0020");
  EXPECT_EQ(hex(deviation_colour(white - 0.5 * half, white, half)), "#92c5de");
  EXPECT_EQ(hex(deviation_colour(white + 0.5 * half, white, half)), "#f4a582");
  // Bluer the shorter, redder the more over.
  double last_blue = 2.0, last_red = -1.0;
  for (double d = -half; d <= half; d += 0.5) {
    const render::Rgb c = deviation_colour(white + d, white, half);
    if (d <= 0) {
      EXPECT_LE(c.b - c.r, last_blue) << d;
      last_blue = c.b - c.r;
    } else {
      EXPECT_GE(c.r - c.b, last_red) << d;
      last_red = c.r - c.b;
    }
  }
  // Not a number (nothing measured there) is drawn neutral, not as an extreme.
  EXPECT_EQ(hex(deviation_colour(std::numeric_limits<double>::quiet_NaN(), white, half)), "#f7f7f7");
}

}  // namespace
}  // namespace beadtwin::scenarios
