#include "render/shading.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace beadtwin::render::shading {
namespace {

TEST(Shading, WholePowerIsThePowerToFloatPrecision) {
  EXPECT_EQ(whole_power(0.7f, 0), 1.0f);
  EXPECT_EQ(whole_power(0.7f, 1), 0.7f);
  EXPECT_EQ(whole_power(0.0f, 24), 0.0f);
  EXPECT_EQ(whole_power(1.0f, 24), 1.0f);
  for (const int n : {2, 3, 5, 8, 24, 33})
    for (float x = 0.0f; x <= 1.0f; x += 0.0625f) {
      const double exact = std::pow(static_cast<double>(x), n);
      // Each of the at most 2 log2(n) multiplications rounds once.
      EXPECT_NEAR(whole_power(x, n), exact, 16.0 * std::numeric_limits<float>::epsilon() * exact)
          << x << "^" << n;
    }
}

}  // namespace
}  // namespace beadtwin::render::shading
