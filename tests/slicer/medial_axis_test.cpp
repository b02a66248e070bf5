#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "slicer/medial_axis.hpp"
#include "slicer/polygons.hpp"

namespace beadtwin::slicer {
namespace {

constexpr double kNoLimit = std::numeric_limits<double>::infinity();

Polygon rectangle(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

// `n` points on a circle from angle a0 to a1 (radians), both ends included.
Polyline arc(double radius, double a0, double a1, int n) {
  Polyline out;
  for (int k = 0; k <= n; ++k) {
    const double a = a0 + (a1 - a0) * k / n;
    out.push_back({radius * std::cos(a), radius * std::sin(a)});
  }
  return out;
}

double length(const CentreLine& c) {
  double l = 0;
  for (std::size_t k = 1; k < c.points.size(); ++k) l += (c.points[k] - c.points[k - 1]).norm();
  return l;
}

TEST(MedialAxis, RectangleGivesOneLineDownItsMiddle) {
  const auto lines = medial_axis({rectangle(0, 0, 200, 10)}, 0, 20);
  ASSERT_EQ(lines.size(), 1u);
  const CentreLine& c = lines[0];
  ASSERT_EQ(c.points.size(), c.width_mm.size());
  EXPECT_GE(length(c), 180.0);
  EXPECT_LE(length(c), 200.0);
  for (std::size_t k = 0; k < c.points.size(); ++k) {
    EXPECT_NEAR(c.points[k].y(), 5.0, 0.05);
    EXPECT_NEAR(c.width_mm[k], 10.0, 0.1);
  }
  // The branches into the corners are pruned: the line stops half the width short of each end.
  const auto [lo, hi] = std::minmax(c.points.front().x(), c.points.back().x());
  EXPECT_NEAR(lo, 5.0, 0.01);
  EXPECT_NEAR(hi, 195.0, 0.01);
}

TEST(MedialAxis, TaperedWedgeWidthFollowsTheTaper) {
  // 300 long, 10 wide at x = 0 and 2 wide at x = 300, symmetric about y = 0.
  const Polygon wedge{{0, -5}, {300, -1}, {300, 1}, {0, 5}};
  auto lines = medial_axis({wedge}, 0, 20);
  ASSERT_EQ(lines.size(), 1u);
  CentreLine c = lines[0];
  if (c.points.front().x() > c.points.back().x()) {
    std::reverse(c.points.begin(), c.points.end());
    std::reverse(c.width_mm.begin(), c.width_mm.end());
  }
  EXPECT_GT(length(c), 290.0);
  // Thickness across the wall: twice the distance from (x, 0) to a side, which rises 4 in 300.
  const double slope = 4.0 / 300.0;
  for (std::size_t k = 0; k < c.points.size(); ++k) {
    const double x = c.points[k].x();
    EXPECT_NEAR(c.points[k].y(), 0.0, 1e-3);
    const double thickness = 2.0 * (5.0 - slope * x) / std::sqrt(1.0 + slope * slope);
    EXPECT_NEAR(c.width_mm[k], thickness, 0.02 * thickness) << "at x = " << x;
    if (k > 0) {
      EXPECT_LT(c.width_mm[k], c.width_mm[k - 1]);
    }
  }
  EXPECT_NEAR(c.width_mm.front(), 10.0, 0.2);
  EXPECT_NEAR(c.width_mm.back(), 2.0, 0.1);
}

TEST(MedialAxis, CurvedWallFollowsItsMeanRadius) {
  // Half an annulus: mean radius 150, 12 thick, each arc in 1° steps.
  const double pi = std::numbers::pi;
  Polygon sector = arc(156, 0, pi, 180);
  for (const auto& p : arc(144, pi, 0, 180)) sector.push_back(p);
  const auto lines = medial_axis({sector}, 0, 20);
  ASSERT_EQ(lines.size(), 1u);
  const CentreLine& c = lines[0];
  double a_lo = pi, a_hi = 0;
  for (std::size_t k = 0; k < c.points.size(); ++k) {
    EXPECT_NEAR(c.points[k].norm(), 150.0, 0.3);
    EXPECT_NEAR(c.width_mm[k], 12.0, 0.12);
    const double a = std::atan2(c.points[k].y(), c.points[k].x());
    a_lo = std::min(a_lo, a);
    a_hi = std::max(a_hi, a);
  }
  EXPECT_LT(a_lo, 0.1);
  EXPECT_GT(a_hi, pi - 0.1);
  // The inner arc's points are concave corners: the line is the parabolas round them, split finely.
  EXPECT_GT(c.points.size(), 360u);
}

// Distance from p to the nearest contour of a region.
double distance_to_outline(const Polygons& region, const Eigen::Vector2d& p) {
  double d = std::numeric_limits<double>::infinity();
  for (const Polygon& poly : region)
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Eigen::Vector2d a = poly[i], ab = poly[(i + 1) % poly.size()] - a;
      const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      d = std::min(d, (a + t * ab - p).norm());
    }
  return d;
}

TEST(MedialAxis, CurvesAreSplitWithinTolerance) {
  // An L of two 10-wide legs: round the inner corner the centre line is two parabolas (focus the corner,
  // directrix an outer side), 2% off their chord. Halfway along each piece of polyline, twice the distance to
  // the outline must match the width there to 1%.
  const Polygons ell{{{0, 0}, {100, 0}, {100, 10}, {10, 10}, {10, 100}, {0, 100}}};
  const auto lines = medial_axis(ell, 0, 20);
  ASSERT_EQ(lines.size(), 1u);
  const CentreLine& c = lines[0];
  for (std::size_t k = 1; k < c.points.size(); ++k) {
    const double w = 0.5 * (c.width_mm[k - 1] + c.width_mm[k]);
    const Eigen::Vector2d m = 0.5 * (c.points[k - 1] + c.points[k]);
    EXPECT_NEAR(2.0 * distance_to_outline(ell, m), w, 0.01 * w) << "at " << m.transpose();
  }
  EXPECT_GT(c.points.size(), 6u);  // the parabolas are split
}

TEST(MedialAxis, TeeGivesThreeLinesMeetingAtTheJunction) {
  // A bar [-100, 100] x [90, 100] on a stem [-5, 5] x [0, 90]: both 10 wide, centre lines meeting at (0, 95).
  const Polygon tee{{-5, 0}, {5, 0}, {5, 90}, {100, 90}, {100, 100}, {-100, 100}, {-100, 90}, {-5, 90}};
  const auto lines = medial_axis({tee}, 0, 20);
  ASSERT_EQ(lines.size(), 3u);
  const Eigen::Vector2d junction{0, 95};
  std::vector<Eigen::Vector2d> meeting;
  for (const CentreLine& c : lines) {
    const Eigen::Vector2d& end = (c.points.front() - junction).norm() < (c.points.back() - junction).norm()
                                     ? c.points.front()
                                     : c.points.back();
    EXPECT_LT((end - junction).norm(), 10.0);
    meeting.push_back(end);
    EXPECT_GT(length(c), 80.0);
  }
  EXPECT_LT((meeting[0] - meeting[1]).norm(), 1e-6);
  EXPECT_LT((meeting[0] - meeting[2]).norm(), 1e-6);
}

TEST(MedialAxis, WidthLimitKeepsTheLineOutOfWideParts) {
  // A 10-wide strip [60, 160] x [25, 35] on the side of a 60 x 60 square.
  const Polygon flag{{0, 0}, {60, 0}, {60, 25}, {160, 25}, {160, 35}, {60, 35}, {60, 60}, {0, 60}};
  const Eigen::Vector2d middle{30, 30};
  const auto lines = medial_axis({flag}, 0, 20);
  ASSERT_EQ(lines.size(), 1u);
  const CentreLine& c = lines[0];
  double x_lo = 1e9, x_hi = -1e9;
  for (std::size_t k = 0; k < c.points.size(); ++k) {
    EXPECT_LE(c.width_mm[k], 20.0 + 1e-6);
    EXPECT_GT((c.points[k] - middle).norm(), 15.0);
    x_lo = std::min(x_lo, c.points[k].x());
    x_hi = std::max(x_hi, c.points[k].x());
  }
  EXPECT_LT(x_lo, 60.0);  // the whole strip, and a little way into the square where it is still narrow
  EXPECT_GT(x_hi, 150.0);
  // The line ends where the width reaches the limit: between the two corners at (60, 25) and (60, 35),
  // 2·sqrt((60 − x)² + 5²) = 20 at x = 60 − sqrt(75).
  EXPECT_NEAR(x_lo, 60.0 - std::sqrt(75.0), 1e-3);

  // Without the limit the same region's lines do reach the square's middle.
  bool reaches = false;
  for (const CentreLine& l : medial_axis({flag}, 0, kNoLimit))
    for (const auto& p : l.points) reaches = reaches || (p - middle).norm() < 15.0;
  EXPECT_TRUE(reaches);

  // A lower limit drops the strip and keeps only the wider part.
  for (const CentreLine& l : medial_axis({flag}, 12, 20))
    for (double w : l.width_mm) EXPECT_GE(w, 12.0 - 1e-6);
}

TEST(MedialAxis, RingGivesOneClosedLoop) {
  const double pi = std::numbers::pi;
  Polygon outer = arc(104, 0, 2 * pi, 256);
  outer.pop_back();
  Polygon hole = arc(96, 2 * pi, 0, 256);  // clockwise
  hole.pop_back();
  const auto lines = medial_axis({outer, hole}, 0, 20);
  ASSERT_EQ(lines.size(), 1u);
  const CentreLine& c = lines[0];
  EXPECT_EQ(c.points.front(), c.points.back());
  EXPECT_EQ(c.width_mm.front(), c.width_mm.back());
  for (std::size_t k = 0; k < c.points.size(); ++k) {
    EXPECT_NEAR(c.points[k].norm(), 100.0, 0.3);
    EXPECT_NEAR(c.width_mm[k], 8.0, 0.08);
  }
  EXPECT_NEAR(length(c), 2 * pi * 100.0, 1.0);
}

TEST(MedialAxis, EmptyInputGivesNoLines) {
  EXPECT_TRUE(medial_axis({}, 0, 20).empty());
  EXPECT_TRUE(medial_axis({Polygon{}}, 0, 20).empty());
}

TEST(MedialAxis, DegenerateInputGivesNoLinesOrValidOnes) {
  const std::vector<Polygons> cases{
      {rectangle(0, 0, 1e-5, 1e-5)},                              // below the 1 µm grid
      {{{0, 0}, {10, 0}, {20, 0}}},                               // collinear
      {{{0, 0}, {10, 0}}},                                        // two points
      {rectangle(0, 0, 10, 10), rectangle(10, 10, 20, 20)},       // touching at a corner
      {{{0, 0}, {20, 10}, {20, 0}, {0, 10}}},                     // a bow tie, crossing itself
      {rectangle(0, 0, 10, 10), rectangle(0, 0, 10, 10)},         // the same square twice
      {rectangle(0, 0, 30, 10), rectangle(10, 0, 20, 10)},        // overlapping
      {rectangle(0, 0, 10, 10), {{5, 10}, {10, 20}, {0, 20}}},    // a corner touching an edge
      {rectangle(0, 0, 30, 30), {{10, 10}, {10, 20}, {30, 15}}},  // a hole touching the outline
      {rectangle(0, 0, 1e-3, 100)},                               // one grid step wide
  };
  for (const Polygons& region : cases) {
    std::vector<CentreLine> lines;
    ASSERT_NO_THROW(lines = medial_axis(region, 0, kNoLimit));
    for (const CentreLine& c : lines) {
      ASSERT_GE(c.points.size(), 2u);
      ASSERT_EQ(c.points.size(), c.width_mm.size());
      for (std::size_t k = 0; k < c.points.size(); ++k) {
        EXPECT_TRUE(c.points[k].allFinite());
        EXPECT_TRUE(contains(union_nonzero(region), c.points[k]) || c.width_mm[k] < 1e-3);
        EXPECT_GE(c.width_mm[k], 0.0);
      }
    }
  }
  // Squares touching at a corner: their medial axes are all branches into square corners, and nothing is
  // made up across the touch.
  EXPECT_TRUE(medial_axis({rectangle(0, 0, 10, 10), rectangle(10, 10, 20, 20)}, 0, kNoLimit).empty());
}

TEST(MedialAxis, FarFromTheOriginGivesTheSameLine) {
  // 9 m and 5 km out: the grid is taken about the region, so the line is the same, shifted.
  for (const double offset : {9000.0, 5e6}) {
    const Eigen::Vector2d shift{offset, -offset};
    Polygon r = rectangle(0, 0, 200, 10);
    for (auto& p : r) p += shift;
    const auto lines = medial_axis({r}, 0, 20);
    ASSERT_EQ(lines.size(), 1u) << offset;
    for (std::size_t k = 0; k < lines[0].points.size(); ++k) {
      EXPECT_NEAR(lines[0].points[k].y() - shift.y(), 5.0, 1e-6);
      EXPECT_NEAR(lines[0].width_mm[k], 10.0, 1e-6);
    }
  }
  // A region 10 km across is past int32 at 1 µm: it gets a coarser grid (about 5 µm) and still its lines.
  const auto lines =
      medial_axis({rectangle(-5e6, 0, -5e6 + 200, 10), rectangle(5e6 - 200, 0, 5e6, 10)}, 0, 20);
  ASSERT_EQ(lines.size(), 2u);
  for (const CentreLine& c : lines) {
    EXPECT_NEAR(length(c), 190.0, 0.02);
    for (std::size_t k = 0; k < c.points.size(); ++k) {
      EXPECT_NEAR(c.points[k].y(), 5.0, 0.01);
      EXPECT_NEAR(c.width_mm[k], 10.0, 0.02);
    }
  }
}

TEST(MedialAxis, SharpTipKeepsItsBranch) {
  // A spike 100 long and 10 wide at its base (tip angle about 5.7°): its line runs into the tip, cut where
  // the spike gets thinner than the minimum width.
  const Polygon spike{{0, -5}, {100, 0}, {0, 5}};
  const auto lines = medial_axis({spike}, 1.0, 20);
  ASSERT_EQ(lines.size(), 1u);
  const CentreLine& c = lines[0];
  const auto [lo, hi] = std::minmax(c.points.front().x(), c.points.back().x());
  // Thickness at x: twice the distance from (x, 0) to a side, 1 where x = 100 − 0.5·sqrt(100² + 5²)/5.
  EXPECT_NEAR(hi, 100.0 - 0.5 * std::sqrt(100.0 * 100.0 + 25.0) / 5.0, 1e-3);
  EXPECT_LT(lo, 10.0);
  EXPECT_NEAR(std::min(c.width_mm.front(), c.width_mm.back()), 1.0, 1e-6);
}

TEST(MedialAxis, BadArgumentsAreInternalErrors) {
  EXPECT_THROW(medial_axis({rectangle(0, 0, 10, 10)}, 5, 2), InternalError);
  EXPECT_THROW(medial_axis({rectangle(0, 0, 10, 10)}, -1, 2), InternalError);
  EXPECT_THROW(medial_axis({{{0, 0}, {std::nan(""), 0}, {0, 1}}}, 0, 2), InternalError);
}

}  // namespace
}  // namespace beadtwin::slicer
