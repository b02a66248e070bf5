// Tests of the branch-and-bound search for the least and the most stock (sim/stock_extremes.hpp) on a
// stock given by a formula: the distance to a point, less a radius (a ball of material's surface), which
// changes no faster than the point moves, as a stock does.
#include "sim/stock_extremes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "sim/triangle_sampling.hpp"

namespace beadtwin::sim {
namespace {

using Vec3 = Eigen::Vector3d;

constexpr double kSpacing = 2.0, kBand = 20.0, kTolerance = 0.01;

// A square 10 x 10 mm in the plane z = 0, two triangles, sampled every 2 mm, the stock at each sample.
struct Square {
  std::vector<SampledTriangle> triangles;
  std::vector<StockSample> samples;
  double least = std::numeric_limits<double>::infinity(), most = -least;  // the samples'

  Square(const StockProbe& stock, bool on_plate = false) {
    const Vec3 a(0, 0, 0), b(10, 0, 0), c(10, 10, 0), d(0, 10, 0);
    for (const auto& [p, q, r] : {std::array<Vec3, 3>{a, b, c}, std::array<Vec3, 3>{a, c, d}}) {
      SampledTriangle t{p, q, r};
      t.first_sample = samples.size();
      t.on_plate = on_plate;
      for_each_cell(p, q, r, kSpacing, [&](const SampleCell& cell) {
        samples.push_back({stock(cell.point, kBand), cell.area, on_plate});
      });
      t.samples = samples.size() - t.first_sample;
      triangles.push_back(t);
    }
    for (const StockSample& s : samples) {
      least = std::min(least, s.stock_mm);
      most = std::max(most, s.stock_mm);
    }
  }
};

ExtremeSearch search() {
  ExtremeSearch s;
  s.spacing_mm = kSpacing;
  s.band_mm = kBand;
  s.tolerance_mm = kTolerance;
  return s;
}

// The stock 3 mm short of a point in the square (least −3 mm there) and growing away from it: the samples
// miss both extremes; the search finds the least at the point and the most at the farthest corner.
TEST(StockExtremes, FindsTheExtremesBetweenTheSamples) {
  const Vec3 centre(3.3, 6.1, 0.0);
  std::size_t calls = 0;
  const StockProbe stock = [&](const Vec3& p, double) {
    ++calls;
    return (p - centre).norm() - 3.0;
  };
  const Square square(stock);
  double least = square.least, most = square.most;
  ASSERT_GT(least, -3.0 + 10 * kTolerance);  // the samples alone miss the least by more than the tolerance
  const double farthest = (Vec3(10, 0, 0) - centre).norm() - 3.0;
  ASSERT_LT(most, farthest - 10 * kTolerance);
  calls = 0;
  sharpen_stock_extremes(square.triangles, square.samples, stock, search(), least, most);
  EXPECT_NEAR(least, -3.0, kTolerance);
  EXPECT_GE(least, -3.0);
  EXPECT_NEAR(most, farthest, kTolerance);
  EXPECT_LE(most, farthest);
  EXPECT_GT(calls, 0u);
  EXPECT_LT(calls, 5000u);  // a search, not a fine sampling of the whole square
}

// No measurement allowed, or every sample on the plate: the samples' extremes stay.
TEST(StockExtremes, KeepsTheSamplesExtremesWhenNothingMayBeMeasured) {
  const StockProbe stock = [](const Vec3& p, double) { return (p - Vec3(3.3, 6.1, 0.0)).norm() - 3.0; };
  const Square square(stock);
  ExtremeSearch none = search();
  none.max_measurements = 0;
  double least = square.least, most = square.most;
  sharpen_stock_extremes(square.triangles, square.samples, stock, none, least, most);
  EXPECT_EQ(least, square.least);
  EXPECT_EQ(most, square.most);
  const Square plate(stock, /*on_plate=*/true);
  ExtremeSearch on_plate = search();
  on_plate.plate_top_mm = 1.0;
  least = 7.0, most = 8.0;
  sharpen_stock_extremes(plate.triangles, plate.samples, stock, on_plate, least, most);
  EXPECT_EQ(least, 7.0);
  EXPECT_EQ(most, 8.0);
}

// A stock beyond the band either way is bounded by it: a plateau at the band's edge stops the search.
TEST(StockExtremes, NoExtremeBeyondTheBand) {
  const StockProbe stock = [](const Vec3& p, double) { return std::clamp(p.x() - 25.0, -kBand, kBand); };
  const Square square(stock);
  double least = square.least, most = square.most;
  ASSERT_EQ(least, -kBand);
  sharpen_stock_extremes(square.triangles, square.samples, stock, search(), least, most);
  EXPECT_EQ(least, -kBand);
  EXPECT_NEAR(most, -15.0, kTolerance);
}

}  // namespace
}  // namespace beadtwin::sim
