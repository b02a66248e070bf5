#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "slicer/fill_styles.hpp"
#include "slicer/polygons.hpp"

namespace beadtwin::slicer {
namespace {

constexpr double kW = 20.0;  // bead width, mm
constexpr double kPitch = kW * 0.9;

Polygon rectangle(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

// The hole of the plate, as a box.
struct Box {
  double x0, y0, x1, y1;
};
constexpr Box kHole{300, 150, 450, 270};

// 600 x 400 plate with an off-centre 150 x 120 hole.
Polygons plate() {
  Polygon hole = rectangle(kHole.x0, kHole.y0, kHole.x1, kHole.y1);
  std::reverse(hole.begin(), hole.end());
  return {rectangle(0, 0, 600, 400), hole};
}
// 600 x 400 L, the arm 300 wide above a step at `step`. At 220 the bead-centre region's step (210) lies
// 1 mm above a fill row (rows at 11 + 18 k): uniform-pitch styles leave a strip up to one pitch wide along
// an edge parallel to the lines that falls between rows (at 200 the zigzags cover 96 %).
Polygons l_shape(double step = 220) {
  return {{{0, 0}, {600, 0}, {600, step}, {300, step}, {300, 400}, {0, 400}}};
}
// Where bead centres may go: half a bead inside the outline.
Polygons centres(const Polygons& outline) {
  return offset(outline, -0.5 * kW);
}

struct Seg {
  Eigen::Vector2d a, b;
  bool print = true;
  bool corner = false;
  std::size_t path = 0;
  double length() const { return (b - a).norm(); }
};

std::vector<Seg> flatten(const std::vector<FillPath>& paths) {
  std::vector<Seg> out;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    Eigen::Vector2d at = paths[i].start;
    for (const FillSegment& s : paths[i].segments) {
      out.push_back({at, s.to, s.print, s.corner, i});
      at = s.to;
    }
  }
  return out;
}

// Printing straight fill lines (not turns).
std::vector<Seg> lines_of(const std::vector<FillPath>& paths) {
  std::vector<Seg> out;
  for (const Seg& s : flatten(paths))
    if (s.print && !s.corner && s.length() > 1e-6) out.push_back(s);
  return out;
}

// A bead of width `w` along a..b with round ends (what the melt spreads to).
Polygon capsule(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double w) {
  const Eigen::Vector2d d =
      (b - a).norm() > 1e-9 ? Eigen::Vector2d((b - a).normalized()) : Eigen::Vector2d(1, 0);
  const double base = std::atan2(d.y(), d.x());
  Polygon out;
  for (int k = 0; k <= 16; ++k) {
    const double t = base - 0.5 * std::numbers::pi + std::numbers::pi * k / 16;
    out.push_back(b + 0.5 * w * Eigen::Vector2d(std::cos(t), std::sin(t)));
  }
  for (int k = 0; k <= 16; ++k) {
    const double t = base + 0.5 * std::numbers::pi + std::numbers::pi * k / 16;
    out.push_back(a + 0.5 * w * Eigen::Vector2d(std::cos(t), std::sin(t)));
  }
  return out;
}

// Fraction of the part the beads should cover (the bead-centre region grown by w/2, within the outline)
// that the printed segments cover.
double coverage(const std::vector<FillPath>& paths, const Polygons& outline) {
  Polygons beads;
  for (const Seg& s : flatten(paths))
    if (s.print) beads.push_back(capsule(s.a, s.b, kW));
  const Polygons target = intersection(offset(centres(outline), 0.5 * kW), outline);
  return area_mm2(intersection(union_nonzero(beads), target)) / area_mm2(target);
}

double distance_to_box(const Eigen::Vector2d& p, const Box& b) {
  const double dx = std::max({b.x0 - p.x(), 0.0, p.x() - b.x1});
  const double dy = std::max({b.y0 - p.y(), 0.0, p.y() - b.y1});
  return std::hypot(dx, dy);
}

// Whether the segment passes through the inside of the box (Liang-Barsky).
bool crosses(const Seg& s, const Box& box) {
  const double e = 1e-6;
  const Eigen::Vector2d d = s.b - s.a;
  double t0 = 0, t1 = 1;
  const double p[] = {-d.x(), d.x(), -d.y(), d.y()};
  const double q[] = {s.a.x() - (box.x0 + e), (box.x1 - e) - s.a.x(), s.a.y() - (box.y0 + e),
                      (box.y1 - e) - s.a.y()};
  for (int i = 0; i < 4; ++i) {
    if (std::abs(p[i]) < 1e-15) {
      if (q[i] < 0) return false;
      continue;
    }
    const double t = q[i] / p[i];
    if (p[i] < 0) t0 = std::max(t0, t);
    if (p[i] > 0) t1 = std::min(t1, t);
  }
  return t0 < t1;
}

// Turn (radians, unsigned) from the direction u to v.
double turn_between(const Eigen::Vector2d& u, const Eigen::Vector2d& v) {
  return std::abs(std::atan2(u.x() * v.y() - u.y() * v.x(), u.dot(v)));
}

FillPattern pattern(FillStyle style) {
  FillPattern f;
  f.style = style;
  f.bead_width_mm = kW;
  f.overlap = 0.1;
  return f;
}

const FillStyle kSolidStyles[] = {FillStyle::kOneWay, FillStyle::kSimpleZigzag, FillStyle::kSmartZigzag,
                                  FillStyle::kSmartZigzagConstantOverlap, FillStyle::kSparseZigzag};

TEST(FillStyle, SolidStylesCoverThePlateAndPrintNothingOverTheHole) {
  const Polygons outline = plate();
  for (const FillStyle style : kSolidStyles) {
    SCOPED_TRACE("style " + std::to_string(static_cast<int>(style)));
    const auto paths = plan_fill(centres(outline), pattern(style));
    ASSERT_FALSE(paths.empty());
    EXPECT_GE(coverage(paths, outline), 0.97);
    for (const Seg& s : flatten(paths)) {
      if (!s.print) continue;
      EXPECT_GE(distance_to_box(s.a, kHole), 0.5 * kW - 1e-6);
      EXPECT_GE(distance_to_box(s.b, kHole), 0.5 * kW - 1e-6);
      EXPECT_GE(distance_to_box(0.5 * (s.a + s.b), kHole), 0.5 * kW - 1e-6);
    }
  }
}

TEST(FillStyle, SolidStylesCoverTheLShape) {
  const Polygons outline = l_shape();
  for (const FillStyle style : kSolidStyles) {
    SCOPED_TRACE("style " + std::to_string(static_cast<int>(style)));
    const auto paths = plan_fill(centres(outline), pattern(style));
    EXPECT_GE(coverage(paths, outline), 0.97);
    // Every printed move keeps its bead centre inside the region.
    const Polygons grown = offset(centres(outline), 1e-3);
    for (const Seg& s : flatten(paths)) {
      if (s.print) {
        EXPECT_TRUE(contains(grown, 0.5 * (s.a + s.b)));
      }
    }
  }
}

TEST(FillStyle, OneWayLinesAllRunTheSameWayAndHopOverTheHole) {
  const auto paths = plan_fill(centres(plate()), pattern(FillStyle::kOneWay));
  const auto lines = lines_of(paths);
  ASSERT_FALSE(lines.empty());
  for (const Seg& s : lines) EXPECT_GT((s.b - s.a).normalized().dot(Eigen::Vector2d(1, 0)), 1 - 1e-9);
  int hops = 0;
  for (const Seg& s : flatten(paths)) {
    EXPECT_FALSE(s.corner);
    if (!s.print && crosses(s, kHole)) ++hops;
    if (s.print) {
      EXPECT_FALSE(crosses(s, kHole));
    }
  }
  EXPECT_GT(hops, 0);
  // One path per line: the return to the next line's start is a travel between paths.
  std::set<long> rows;
  for (const Seg& s : lines) rows.insert(std::lround(s.a.y() * 1000));
  EXPECT_EQ(paths.size(), rows.size());
}

TEST(FillStyle, SimpleZigzagCrossesTheHoleOnlyWithoutPrinting) {
  const auto paths = plan_fill(centres(plate()), pattern(FillStyle::kSimpleZigzag));
  int hops = 0, turns = 0;
  for (const Seg& s : flatten(paths)) {
    if (s.print) {
      EXPECT_FALSE(crosses(s, kHole));
    }
    if (!s.print && crosses(s, kHole)) ++hops;
    if (s.corner) ++turns;
  }
  EXPECT_GT(hops, 0);
  EXPECT_GT(turns, 10);
  EXPECT_EQ(paths.size(), 1u);  // a plain rectangle outside: one serpentine
}

TEST(FillStyle, SmartZigzagNeverCrossesTheHoleWithinAPath) {
  const auto paths = plan_fill(centres(plate()), pattern(FillStyle::kSmartZigzag));
  for (const Seg& s : flatten(paths)) {
    EXPECT_FALSE(crosses(s, kHole));
    EXPECT_TRUE(s.print);
  }
  EXPECT_GT(paths.size(), 1u);  // the cells beside the hole need travels
  EXPECT_LE(paths.size(), 4u);  // four cells at most
  // The rows beside the hole stop at it on both sides.
  bool left = false, right = false;
  for (const Seg& s : lines_of(paths)) {
    if (s.a.y() <= 140 || s.a.y() >= 280) continue;
    left = left || std::abs(std::max(s.a.x(), s.b.x()) - 290) < 1e-6;
    right = right || std::abs(std::min(s.a.x(), s.b.x()) - 460) < 1e-6;
  }
  EXPECT_TRUE(left && right);
}

TEST(FillStyle, TurnsStayInsideTheRegionHoweverLongTheyMayBe) {
  // A slit 4 mm high cut 200 mm into the plate's side, between two fill rows: with no length limit only
  // the turn region keeps the turn from the row below it to the shortened row beside it off the slit.
  const Box slit{400, 205, 600, 209};
  const Polygons outline{
      {{0, 0}, {600, 0}, {600, 205}, {400, 205}, {400, 209}, {600, 209}, {600, 400}, {0, 400}}};
  for (const FillStyle style : {FillStyle::kSimpleZigzag, FillStyle::kSmartZigzag}) {
    FillPattern f = pattern(style);
    f.turn_link_max_mm = 1000;
    const auto paths = plan_fill(centres(outline), f);
    for (const Seg& s : flatten(paths)) {
      if (s.print) {
        EXPECT_FALSE(crosses(s, slit));
      }
    }
    EXPECT_GE(coverage(paths, outline), 0.97);
  }
}

// Distinct heights of lines, sorted.
std::vector<double> heights(const std::vector<Seg>& lines) {
  std::vector<double> ys;
  for (const Seg& s : lines) ys.push_back(s.a.y());
  std::sort(ys.begin(), ys.end());
  ys.erase(std::unique(ys.begin(), ys.end(), [](double a, double b) { return b - a < 1e-6; }), ys.end());
  return ys;
}

// Equal spacing within each group, overlap in range; returns the spacing.
double check_even(const std::vector<double>& ys, const FillPattern& f) {
  EXPECT_GE(ys.size(), 2u);
  if (ys.size() < 2) return 0;
  const double s = ys[1] - ys[0];
  for (std::size_t i = 2; i < ys.size(); ++i) EXPECT_NEAR(ys[i] - ys[i - 1], s, 1e-6);
  EXPECT_GE(1 - s / f.bead_width_mm, f.overlap - 1e-9);
  EXPECT_LE(1 - s / f.bead_width_mm, f.max_overlap + 1e-9);
  return s;
}

TEST(FillStyle, ConstantOverlapDividesEachCellEvenly) {
  const FillPattern f = pattern(FillStyle::kSmartZigzagConstantOverlap);
  const auto lines = lines_of(plan_fill(centres(plate()), f));
  // Cells of the bead-centre region: below the hole [10, 140], beside it (140, 280), above [280, 390].
  std::vector<Seg> below, left, right, above;
  for (const Seg& s : lines) {
    const double y = s.a.y();
    if (y <= 140 + 1e-6)
      below.push_back(s);
    else if (y >= 280 - 1e-6)
      above.push_back(s);
    else
      (std::max(s.a.x(), s.b.x()) <= 290 + 1e-6 ? left : right).push_back(s);
  }
  for (const auto* cell : {&below, &above}) {
    const auto ys = heights(*cell);
    check_even(ys, f);
  }
  // The full-width cells run from edge to edge of their band.
  EXPECT_NEAR(heights(below).front(), 10, 1e-6);
  EXPECT_NEAR(heights(below).back(), 140, 1e-6);
  EXPECT_NEAR(heights(above).front(), 280, 1e-6);
  EXPECT_NEAR(heights(above).back(), 390, 1e-6);
  // Beside the hole the gaps to the lines along the hole's ends are the cell's spacing too.
  for (const auto* cell : {&left, &right}) {
    const auto ys = heights(*cell);
    const double s = check_even(ys, f);
    EXPECT_NEAR(ys.front() - 140, s, 1e-6);
    EXPECT_NEAR(280 - ys.back(), s, 1e-6);
  }
}

TEST(FillStyle, ConstantOverlapFillsUpToAStep) {
  // The L stepped where the rows at the normal pitch leave a 17 mm strip below the step: two cells, the
  // lower one's lines reaching the step's height, the upper one's spaced evenly from there.
  const FillPattern f = pattern(FillStyle::kSmartZigzagConstantOverlap);
  const auto paths = plan_fill(centres(l_shape(200)), f);
  std::vector<Seg> lower, upper;
  for (const Seg& s : lines_of(paths)) (s.a.y() <= 190 + 1e-6 ? lower : upper).push_back(s);
  const auto low = heights(lower), up = heights(upper);
  check_even(low, f);
  const double s = check_even(up, f);
  EXPECT_NEAR(low.front(), 10, 1e-6);
  EXPECT_NEAR(low.back(), 190, 1e-6);
  EXPECT_NEAR(up.front() - 190, s, 1e-6);
  EXPECT_NEAR(up.back(), 390, 1e-6);
  EXPECT_GE(coverage(paths, l_shape(200)), 0.99);
}

TEST(FillStyle, SparseZigzagLeavesGapsFirstThenFillsThem) {
  const Polygons region = centres(plate());
  for (const double max_spacing : {0.0, 60.0}) {
    SCOPED_TRACE("max spacing " + std::to_string(max_spacing));
    FillPattern f = pattern(FillStyle::kSparseZigzag);
    f.max_sparse_spacing_mm = max_spacing;
    const double limit = max_spacing > 0 ? max_spacing : 2 * kW;
    const auto paths = plan_fill(region, f);
    const auto lines = lines_of(paths);
    const auto all = heights(lines);
    ASSERT_GE(all.size(), 3u);
    // The first serpentine: lines up to the first one that lies between two lines laid before it.
    std::vector<Seg> first;
    for (const Seg& s : lines) {
      const auto ys = heights(first);
      const bool in_gap =
          !ys.empty() && s.a.y() > ys.front() + 1e-6 && s.a.y() < ys.back() - 1e-6 &&
          std::none_of(ys.begin(), ys.end(), [&s](double y) { return std::abs(y - s.a.y()) < 1e-6; });
      if (in_gap) break;
      first.push_back(s);
    }
    const auto ys = heights(first);
    ASSERT_GE(ys.size(), 2u);
    for (std::size_t i = 1; i < ys.size(); ++i) {
      EXPECT_LE(ys[i] - ys[i - 1], limit + 1e-6);
      EXPECT_GE(ys[i] - ys[i - 1], 2 * kPitch - 1e-6);  // gaps left for the later passes
    }
    EXPECT_NEAR(ys.front(), all.front(), 1e-6);
    EXPECT_GE(ys.back(), all.back() - limit);
    EXPECT_LT(first.size(), lines.size());
    // Finally every row at the normal pitch, covering like the solid smart zigzag.
    const auto solid = heights(lines_of(plan_fill(region, pattern(FillStyle::kSmartZigzag))));
    ASSERT_EQ(all.size(), solid.size());
    for (std::size_t i = 0; i < all.size(); ++i) EXPECT_NEAR(all[i], solid[i], 1e-6);
    EXPECT_GE(coverage(paths, plate()), 0.97);
  }
}

TEST(FillStyle, AngleTurnsTheLines) {
  const double angle = std::numbers::pi / 6;
  for (const FillStyle style : {FillStyle::kSimpleZigzag, FillStyle::kSmartZigzag}) {
    FillPattern f = pattern(style);
    f.angle_rad = angle;
    const auto paths = plan_fill(centres(plate()), f);
    const Eigen::Vector2d dir(std::cos(angle), std::sin(angle));
    const auto lines = lines_of(paths);
    ASSERT_FALSE(lines.empty());
    for (const Seg& s : lines) EXPECT_GT(std::abs((s.b - s.a).normalized().dot(dir)), 1 - 1e-9);
    // Lines meet the plate's long sides at 30 degrees: turns there would be 36 mm, longer than the default
    // limit (1.5 pitch), so those strips are left to the boundary passes.
    EXPECT_GE(coverage(paths, plate()), 0.95);
    for (const Seg& s : lines) {
      EXPECT_GE(distance_to_box(s.a, kHole), 0.5 * kW - 1e-6);
      EXPECT_GE(distance_to_box(s.b, kHole), 0.5 * kW - 1e-6);
    }
    // Turns may cut a corner of the hole's bead-centre outline (they may leave the region by w/2), but
    // never reach into the hole.
    for (const Seg& s : flatten(paths)) {
      if (s.print) {
        EXPECT_FALSE(crosses(s, kHole));
      }
    }
  }
}

TEST(FillStyle, MinFillLengthDropsShortLines) {
  FillPattern f = pattern(FillStyle::kSmartZigzag);
  const auto beside_hole = [](const Seg& s) { return s.a.y() > 140 && s.a.y() < 280 && s.a.x() > 400; };
  const auto all = lines_of(plan_fill(centres(plate()), f));
  EXPECT_TRUE(std::any_of(all.begin(), all.end(), beside_hole));  // 130 mm long right of the hole
  f.min_fill_length_mm = 200;
  const auto kept = lines_of(plan_fill(centres(plate()), f));
  EXPECT_FALSE(kept.empty());
  for (const Seg& s : kept) EXPECT_GE(s.length(), 200 - 1e-6);
  EXPECT_FALSE(std::any_of(kept.begin(), kept.end(), beside_hole));
}

// Largest turn between consecutive segments of any path, radians.
double sharpest_turn(const std::vector<FillPath>& paths) {
  double worst = 0;
  for (const FillPath& p : paths) {
    Eigen::Vector2d at = p.start, dir = Eigen::Vector2d::Zero();
    for (const FillSegment& s : p.segments) {
      const Eigen::Vector2d d = s.to - at;
      if (d.norm() < 1e-9) continue;
      if (dir.norm() > 0) worst = std::max(worst, turn_between(dir, d));
      dir = d;
      at = s.to;
    }
  }
  return worst;
}

TEST(FillStyle, FilletRoundsTheTurns) {
  FillPattern f = pattern(FillStyle::kSmartZigzag);
  EXPECT_GT(sharpest_turn(plan_fill(centres(plate()), f)), 0.5 * std::numbers::pi - 1e-6);
  for (const double radius : {5.0, 100.0}) {  // 100: capped at half the pitch
    f.fillet_radius_mm = radius;
    const auto paths = plan_fill(centres(plate()), f);
    EXPECT_LT(sharpest_turn(paths), 0.5 * std::numbers::pi - 1e-3);
    EXPECT_GE(coverage(paths, plate()), 0.97);
    // The arc starts where the line ends: a radius (or half the pitch) before the turn.
    double shortest_line = 1e9;
    for (const Seg& s : lines_of(paths)) shortest_line = std::min(shortest_line, s.length());
    EXPECT_LE(shortest_line, 130 - 2 * std::min(radius, 0.5 * kPitch) + 1e-6);
  }
}

TEST(FillStyle, LineExtensionLengthensLines) {
  FillPattern f = pattern(FillStyle::kSmartZigzag);
  const auto longest = [](const std::vector<Seg>& lines) {
    double l = 0;
    for (const Seg& s : lines) l = std::max(l, s.length());
    return l;
  };
  const auto plain = lines_of(plan_fill(centres(plate()), f));
  f.line_extension_mm = 5;
  const auto extended = lines_of(plan_fill(centres(plate()), f));
  EXPECT_NEAR(longest(plain), 580, 1e-6);
  EXPECT_NEAR(longest(extended), 590, 1e-6);
  double x_min = 1e9;
  for (const Seg& s : extended) x_min = std::min({x_min, s.a.x(), s.b.x()});
  EXPECT_NEAR(x_min, 5, 1e-6);
}

TEST(FillStyle, TurnsOutsideSitHalfABeadBeyondTheRegion) {
  const Polygons region{rectangle(10, 10, 590, 390)};
  FillPattern f = pattern(FillStyle::kSmartZigzag);
  const auto turn_xs = [&f, &region] {
    std::set<long> xs;
    for (const Seg& s : flatten(plan_fill(region, f)))
      if (s.corner) xs.insert(std::lround(s.a.x()));
    return xs;
  };
  EXPECT_EQ(turn_xs(), (std::set<long>{10, 590}));
  f.turns_outside = true;
  EXPECT_EQ(turn_xs(), (std::set<long>{0, 600}));
}

TEST(FillStyle, LinkWithRapidsGivesEveryLineItsOwnPath) {
  FillPattern f = pattern(FillStyle::kSmartZigzag);
  f.link_with_rapids = true;
  const auto paths = plan_fill(centres(plate()), f);
  EXPECT_EQ(paths.size(), lines_of(paths).size());
  for (const FillPath& p : paths) EXPECT_EQ(p.segments.size(), 1u);
}

// Trapezoid whose right side leans out 6 mm per pitch: right-hand turns would be slanted.
constexpr double kLean = 6.0 / kPitch;
double right_end(double y) {
  return 400 + kLean * y;
}

TEST(FillStyle, LineMatchingEvensUnevenBridgesUpToTheLimit) {
  const Polygons region{{{0, 0}, {400, 0}, {right_end(300), 300}, {0, 300}}};
  FillPattern f = pattern(FillStyle::kSimpleZigzag);
  const auto right_turns = [](const std::vector<FillPath>& paths) {
    std::vector<Seg> turns;
    for (const Seg& s : flatten(paths))
      if (s.corner && s.a.x() > 200) turns.push_back(s);
    return turns;
  };
  // No limit: a slanted bridge.
  auto paths = plan_fill(region, f);
  auto turns = right_turns(paths);
  ASSERT_GT(turns.size(), 5u);
  for (const Seg& t : turns) EXPECT_NEAR(std::abs(t.b.x() - t.a.x()), 6, 1e-6);
  // Within the limit: the shorter (lower) line runs on to be even with the longer one.
  f.line_matching_limit_mm = 8;
  paths = plan_fill(region, f);
  turns = right_turns(paths);
  ASSERT_GT(turns.size(), 5u);
  int extended = 0;
  for (const Seg& t : turns) {
    EXPECT_NEAR(t.a.x(), t.b.x(), 1e-6);
    EXPECT_NEAR(t.a.x(), right_end(std::max(t.a.y(), t.b.y())), 1e-6);
  }
  for (const Seg& s : lines_of(paths))
    if (std::max(s.a.x(), s.b.x()) > right_end(s.a.y()) + 1) {
      EXPECT_NEAR(std::max(s.a.x(), s.b.x()), right_end(s.a.y()) + 6, 1e-6);
      ++extended;
    }
  EXPECT_EQ(static_cast<std::size_t>(extended), turns.size());
  // Beyond the limit: no extension and no bridge.
  f.line_matching_limit_mm = 3;
  paths = plan_fill(region, f);
  EXPECT_TRUE(right_turns(paths).empty());
  EXPECT_GT(paths.size(), 5u);
  for (const Seg& s : lines_of(paths)) EXPECT_NEAR(std::max(s.a.x(), s.b.x()), right_end(s.a.y()), 1e-6);
}

TEST(FillStyle, BadParametersAreReportedTogether) {
  FillPattern f = pattern(FillStyle::kSmartZigzag);
  f.bead_width_mm = 0;
  f.overlap = 1.2;
  try {
    plan_fill(centres(plate()), f);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("bead width"), std::string::npos) << what;
    EXPECT_NE(what.find("overlap"), std::string::npos) << what;
  }
}

// Sparse gap passes stop short of the first serpentine's turns instead of running over them: where a gap
// pass meets a turn, its bead overlaps the turn's by no more than the pass overlap, and that end is not free.
TEST(FillStyle, SparseGapPassesStopShortOfTheTurns) {
  FillPattern f;
  f.style = FillStyle::kSparseZigzag;
  f.bead_width_mm = kW;
  f.overlap = 0.1;
  f.max_sparse_spacing_mm = 3 * kW * 0.9;
  const std::vector<FillPath> paths = plan_fill(centres({{{0, 0}, {600, 0}, {600, 400}, {0, 400}}}), f);
  const std::vector<Seg> segs = flatten(paths);
  int pulled_back = 0;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    for (const bool at_end : {false, true}) {
      if (at_end ? paths[i].free_end : paths[i].free_start) continue;
      ++pulled_back;
      const Eigen::Vector2d p = at_end ? paths[i].segments.back().to : paths[i].start;
      double nearest = 1e9;
      for (const Seg& s : segs) {
        if (!s.corner || s.path >= i) continue;
        const Eigen::Vector2d d = s.b - s.a;
        const double t = std::clamp((p - s.a).dot(d) / d.squaredNorm(), 0.0, 1.0);
        nearest = std::min(nearest, (s.a + t * d - p).norm());
      }
      // The gap bead's square end lies w/2 − overlap·w from the turn's centre line: they overlap by 10 %.
      EXPECT_NEAR(nearest, kW * (0.5 - 0.1), 1e-6);
    }
  }
  EXPECT_GT(pulled_back, 10);
}

}  // namespace
}  // namespace beadtwin::slicer
