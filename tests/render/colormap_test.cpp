#include "render/colormap.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace beadtwin::render {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

Rgb hex(int rgb) {
  return {static_cast<float>((rgb >> 16) & 0xff) / 255.0f, static_cast<float>((rgb >> 8) & 0xff) / 255.0f,
          static_cast<float>(rgb & 0xff) / 255.0f};
}

// CIE L* of a display sRGB colour (IEC 61966-2-1 decoding, CIE 1976 lightness), written out here rather than
// taken from colormap.cpp so that the test does not share its mistakes.
double lightness(Rgb c) {
  const auto linear = [](double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); };
  const double y = 0.2126 * linear(c.r) + 0.7152 * linear(c.g) + 0.0722 * linear(c.b);
  return y > 216.0 / 24389.0 ? 116.0 * std::cbrt(y) - 16.0 : y * 24389.0 / 27.0;
}

void expect_colour_near(Rgb actual, Rgb expected, double tolerance, const std::string& what) {
  EXPECT_NEAR(actual.r, expected.r, tolerance) << what;
  EXPECT_NEAR(actual.g, expected.g, tolerance) << what;
  EXPECT_NEAR(actual.b, expected.b, tolerance) << what;
}

TEST(ColourMap, SequentialMapsRiseInLightness) {
  for (const ColourMap& map : {ColourMap::viridis(), ColourMap::inferno()}) {
    double previous = -1.0;
    for (int i = 0; i <= 512; ++i) {
      const double l = lightness(map.at(i / 512.0));
      EXPECT_GT(l, previous) << map.name() << " at " << i / 512.0;
      previous = l;
    }
    EXPECT_GT(lightness(map.at(1.0)) - lightness(map.at(0.0)), 60.0) << map.name();
  }
}

TEST(ColourMap, SequentialMapsEndInTheirPublishedColours) {
  // van der Walt & Smith (2015), matplotlib: viridis #440154 .. #FDE725, inferno #000004 .. #FCFFA4.
  constexpr double kHalfByte = 0.5 / 255.0 + 1e-6;
  expect_colour_near(ColourMap::viridis().at(0.0), hex(0x440154), kHalfByte, "viridis at 0");
  expect_colour_near(ColourMap::viridis().at(1.0), hex(0xFDE725), kHalfByte, "viridis at 1");
  expect_colour_near(ColourMap::inferno().at(0.0), hex(0x000004), kHalfByte, "inferno at 0");
  expect_colour_near(ColourMap::inferno().at(1.0), hex(0xFCFFA4), kHalfByte, "inferno at 1");
}

TEST(ColourMap, SequentialMapsFollowTheirPublishedTenColours) {
  // The ten-colour samples matplotlib gives for each map (cmap(np.linspace(0, 1, 10))): its 256-entry table
  // read at entry floor(256 i / 9). They test the interpolation between the 17 samples colormap.cpp keeps.
  const int viridis[] = {0x440154, 0x482878, 0x3E4A89, 0x31688E, 0x26828E,
                         0x1F9E89, 0x35B779, 0x6DCD59, 0xB4DE2C, 0xFDE725};
  const int inferno[] = {0x000004, 0x1B0C41, 0x4A0C6B, 0x781C6D, 0xA52C60,
                         0xCF4446, 0xED6925, 0xFB9B06, 0xF7D13D, 0xFCFFA4};
  for (int i = 0; i < 10; ++i) {
    const double t = std::min(std::floor(256.0 * i / 9.0), 255.0) / 255.0;
    expect_colour_near(ColourMap::viridis().at(t), hex(viridis[i]), 2.0 / 255.0,
                       "viridis stop " + std::to_string(i));
    expect_colour_near(ColourMap::inferno().at(t), hex(inferno[i]), 2.0 / 255.0,
                       "inferno stop " + std::to_string(i));
  }
}

TEST(ColourMap, DivergingIsWhiteInTheMiddleAndBalancedAtTheEnds) {
  const ColourMap map = ColourMap::diverging();
  const Rgb middle = map.at(0.5);
  EXPECT_GT(std::min({middle.r, middle.g, middle.b}), 0.95f);
  EXPECT_LT(std::max({middle.r, middle.g, middle.b}) - std::min({middle.r, middle.g, middle.b}), 0.02f);
  // Negative is blue, positive red, and neither end looks heavier than the other.
  EXPECT_GT(map.at(0.0).b, map.at(0.0).r + 0.3f);
  EXPECT_GT(map.at(1.0).r, map.at(1.0).b + 0.3f);
  EXPECT_NEAR(lightness(map.at(0.0)), lightness(map.at(1.0)), 8.0);
  // Lightness rises to the middle and falls after it: the map's value is told by lightness on both sides.
  for (int i = 1; i <= 256; ++i) {
    const double t = i / 512.0;
    EXPECT_GT(lightness(map.at(t)), lightness(map.at(t - 1.0 / 512.0))) << t;
    EXPECT_GT(lightness(map.at(1.0 - t)), lightness(map.at(1.0 - t + 1.0 / 512.0))) << 1.0 - t;
  }
}

TEST(ColourMap, ClampsAndGreysOutNaN) {
  const ColourMap map = ColourMap::viridis();
  EXPECT_EQ(map.at(-3.0), map.at(0.0));
  EXPECT_EQ(map.at(7.0), map.at(1.0));
  EXPECT_EQ(map.at(-kInf), map.at(0.0));
  EXPECT_EQ(map.at(kNaN), kNoValueGrey);
  EXPECT_NE(map.at(0.25), map.at(0.75));
}

TEST(ColourMap, CategoriesAreDistinctAndCycle) {
  for (int i = 0; i < 7; ++i) {
    for (int j = i + 1; j < 7; ++j) {
      const Rgb a = category_colour(i), b = category_colour(j);
      const float distance = std::abs(a.r - b.r) + std::abs(a.g - b.g) + std::abs(a.b - b.b);
      EXPECT_GT(distance, 0.25f) << i << " and " << j;
    }
    EXPECT_EQ(category_colour(i + 7), category_colour(i));
  }
  EXPECT_EQ(category_colour(0), hex(0x0072B2));  // Okabe & Ito's blue
  EXPECT_EQ(category_colour(-1), kNoValueGrey);
}

TEST(ScalarScale, MapsLinearlyClampsAndGreysOutNaN) {
  const ScalarScale deviation{-2.0, 2.0, ColourMap::diverging()};
  EXPECT_EQ(deviation.colour(0.0), deviation.map.at(0.5));
  EXPECT_EQ(deviation.colour(1.0), deviation.map.at(0.75));
  EXPECT_EQ(deviation.colour(-2.0), deviation.map.at(0.0));
  EXPECT_EQ(deviation.colour(-50.0), deviation.map.at(0.0));
  EXPECT_EQ(deviation.colour(50.0), deviation.map.at(1.0));
  EXPECT_EQ(deviation.colour(kNaN), kNoValueGrey);
  EXPECT_DOUBLE_EQ((ScalarScale{150.0, 300.0}.fraction(200.0)), 1.0 / 3.0);

  const ScalarScale reversed{10.0, 0.0};
  EXPECT_DOUBLE_EQ(reversed.fraction(10.0), 0.0);
  EXPECT_DOUBLE_EQ(reversed.fraction(2.5), 0.75);
  const ScalarScale point{5.0, 5.0};
  EXPECT_EQ(point.fraction(4.0), 0.0);
  EXPECT_EQ(point.fraction(5.0), 0.5);
  EXPECT_EQ(point.fraction(6.0), 1.0);
  EXPECT_TRUE(std::isnan(ScalarScale{0.0, kInf}.fraction(1.0)));
}

// The step between ticks is 1, 2 or 5 x 10^n and every tick a multiple of it.
void expect_one_two_five(const std::vector<double>& ticks, const std::string& what) {
  ASSERT_GE(ticks.size(), 2u) << what;
  const double step = ticks[1] - ticks[0];
  const double decade = std::pow(10.0, std::floor(std::log10(step) + 1e-9));
  const double m = step / decade;
  EXPECT_TRUE(std::abs(m - 1) < 1e-6 || std::abs(m - 2) < 1e-6 || std::abs(m - 5) < 1e-6)
      << what << ": step " << step;
  for (std::size_t i = 1; i < ticks.size(); ++i)
    EXPECT_NEAR(ticks[i] - ticks[i - 1], step, 1e-6 * step) << what << " tick " << i;
  for (const double t : ticks)
    EXPECT_NEAR(t / step, std::round(t / step), 1e-6 * std::max(1.0, std::abs(t / step)))
        << what << ": " << t;
}

TEST(NiceTicks, OneTwoFiveStepsInsideTheRange) {
  const std::vector<std::pair<double, double>> ranges = {
      {0.0, 1.0},       {150.0, 300.0},   {-37.2, 81.9}, {-1e6, -2e5}, {0.0012, 0.0047},   {1e-9, 3.2e-9},
      {2.5e12, 9.1e12}, {273.15, 573.15}, {-0.5, 0.5},   {0.1, 0.3},   {1000.0, 1000.001}, {-3.0, 7.0}};
  for (const auto& [lo, hi] : ranges) {
    for (const int max_count : {2, 3, 5, 6, 8, 11}) {
      const std::string what =
          std::to_string(lo) + " .. " + std::to_string(hi) + " at most " + std::to_string(max_count);
      const std::vector<double> ticks = nice_ticks(lo, hi, max_count);
      expect_one_two_five(ticks, what);
      for (const double t : ticks) {
        EXPECT_GE(t, lo) << what;
        EXPECT_LE(t, hi) << what;
      }
      if (max_count >= 5) {
        EXPECT_LE(ticks.size(), static_cast<std::size_t>(max_count)) << what;
      }
      EXPECT_TRUE(std::is_sorted(ticks.begin(), ticks.end())) << what;
    }
  }
}

TEST(NiceTicks, Examples) {
  EXPECT_EQ(nice_ticks(0.0, 1.0, 6), (std::vector<double>{0.0, 0.2, 0.4, 0.6, 0.8, 1.0}));
  EXPECT_EQ(nice_ticks(0.0, 1.0, 5), (std::vector<double>{0.0, 0.5, 1.0}));
  EXPECT_EQ(nice_ticks(0.1, 0.3, 3), (std::vector<double>{0.1, 0.2, 0.3}));  // the decimals, exactly
  EXPECT_EQ(nice_ticks(150.0, 300.0, 6), (std::vector<double>{150.0, 200.0, 250.0, 300.0}));
  EXPECT_EQ(nice_ticks(-2.0, 2.0, 5), (std::vector<double>{-2.0, -1.0, 0.0, 1.0, 2.0}));
  EXPECT_EQ(nice_ticks(300.0, 150.0, 6), nice_ticks(150.0, 300.0, 6));  // swapped
  // Two ticks even where max_count allows fewer than any 1-2-5 step gives: [0.1, 0.95] has one multiple of
  // 0.5 and four of 0.2.
  EXPECT_EQ(nice_ticks(0.1, 0.95, 2), (std::vector<double>{0.2, 0.4, 0.6, 0.8}));
}

TEST(NiceTicks, DegenerateRanges) {
  EXPECT_EQ(nice_ticks(5.0, 5.0, 6), (std::vector<double>{5.0}));
  EXPECT_TRUE(nice_ticks(kNaN, 1.0, 6).empty());
  EXPECT_TRUE(nice_ticks(0.0, kInf, 6).empty());
  const std::vector<double> everything = nice_ticks(-1.7e308, 1.7e308, 5);  // hi - lo overflows
  ASSERT_GE(everything.size(), 2u);
  for (const double t : everything) EXPECT_TRUE(std::isfinite(t));
  const double x = 1e20;
  const std::vector<double> narrow = nice_ticks(x, std::nextafter(x, 2 * x), 5);
  EXPECT_GE(narrow.size(), 2u);
}

TEST(TickLabels, FewestDigitsThatTellTicksApart) {
  EXPECT_EQ(tick_labels({0.0, 0.25, 0.5, 0.75, 1.0}),
            (std::vector<std::string>{"0.00", "0.25", "0.50", "0.75", "1.00"}));
  EXPECT_EQ(tick_labels({0.0, 50.0, 100.0, 150.0}), (std::vector<std::string>{"0", "50", "100", "150"}));
  EXPECT_EQ(tick_labels(nice_ticks(0.1, 0.3, 3)), (std::vector<std::string>{"0.1", "0.2", "0.3"}));
  EXPECT_EQ(tick_labels({-2.0, -1.0, 0.0, 1.0, 2.0}), (std::vector<std::string>{"-2", "-1", "0", "1", "2"}));
  EXPECT_EQ(tick_labels({10000.0, 15000.0, 20000.0}), (std::vector<std::string>{"10000", "15000", "20000"}));
  // Scientific only where it is shorter.
  EXPECT_EQ(tick_labels({1e7, 1.5e7, 2e7}), (std::vector<std::string>{"1.0e+07", "1.5e+07", "2.0e+07"}));
  EXPECT_EQ(tick_labels({0.0, 1e-6, 2e-6}), (std::vector<std::string>{"0", "1e-06", "2e-06"}));
  EXPECT_EQ(tick_labels({-0.0, 1.0}), (std::vector<std::string>{"0", "1"}));
  EXPECT_EQ(tick_labels({5.0}), (std::vector<std::string>{"5"}));
  EXPECT_EQ(tick_labels({kNaN, -kInf, 2.0}), (std::vector<std::string>{"nan", "-inf", "2"}));
  EXPECT_TRUE(tick_labels({}).empty());
}

}  // namespace
}  // namespace beadtwin::render
