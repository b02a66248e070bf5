// Section parameters of the patent's general, process and boundary categories (paragraphs (17), (41)-(47),
// (50)): each test fails if its parameter were ignored.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "core/units.hpp"
#include "slicer/centre_beads.hpp"
#include "slicer/mesh.hpp"
#include "slicer/plan.hpp"
#include "slicer/polygons.hpp"

namespace beadtwin::slicer {
namespace {

SectionParams section(double z1, double h, double w, int passes) {
  SectionParams s;
  s.name = "s";
  s.z_min_mm = 0;
  s.z_max_mm = z1;
  s.layer_height_mm = h;
  s.bead_width_mm = w;
  s.print_speed_mm_s = 50;
  s.travel_speed_mm_s = 200;
  s.boundary.passes = passes;
  return s;
}

Polygon rect(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

std::vector<const Move*> prints(const Toolpath& tp, int section = -1, Feature f = Feature::kUnknown) {
  std::vector<const Move*> out;
  for (const Move& m : tp.moves)
    if (m.kind == MoveKind::kPrint && (section < 0 || m.section == section) &&
        (f == Feature::kUnknown || m.feature == f))
      out.push_back(&m);
  return out;
}

double length(const std::vector<const Move*>& moves) {
  double l = 0;
  for (const Move* m : moves) l += m->length_mm();
  return l;
}

// Two boxes that touch at x = 400: "a" at x in [0, 400], "b" at x in [400, 800], both 300 deep.
TriangleMesh touching_boxes(double height) {
  TriangleMesh a = make_box({400, 300, height});
  const TriangleMesh b = make_box({400, 300, height}, {400, 0, 0});
  const int base = static_cast<int>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  const std::size_t a_tris = a.triangles.size();
  for (auto t : b.triangles) a.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  a.body.assign(a.triangles.size(), 1);
  std::fill(a.body.begin(), a.body.begin() + static_cast<std::ptrdiff_t>(a_tris), 0);
  a.body_names = {"a", "b"};
  return a;
}

// Patent (17): section b uses a's wall where they meet; it lays no wall of its own along x = 400, its passes
// run into a's outer bead by the pass overlap, and its fill runs up to that bead.
TEST(SectionParams, SharedWallIsPrintedOnce) {
  const double w = 40, h = 10;
  SectionParams a = section(20, h, w, 2), b = section(20, h, w, 2);
  a.name = "a", a.body = "a";
  b.name = "b", b.body = "b";
  b.fill.enabled = true;
  b.boundary.overlap = 0.1;
  b.fill.overlap = 0.1;
  const Toolpath own = plan_toolpath(touching_boxes(20), {a, b}, {});
  b.shares_wall_with = "a";
  const Toolpath shared = plan_toolpath(touching_boxes(20), {b, a}, {});  // listed first, laid after a

  // b's own wall along x = 400 (centre lines at x = 420 and 456, running in y) is gone.
  auto wall_along_seam = [&](const Toolpath& tp) {
    double l = 0;
    for (const Move* m : prints(tp, -1, Feature::kBoundary))
      if (tp.sections[static_cast<std::size_t>(m->section)] == "b" &&
          std::abs(m->start.x() - m->end.x()) < 1e-6 && m->start.x() < 400 + 2 * w)
        l += m->length_mm();
    return l;
  };
  EXPECT_GT(wall_along_seam(own), 2 * 200.0);
  EXPECT_NEAR(wall_along_seam(shared), 0.0, 1e-9);
  // Its passes end overlap·w inside a, on a's outer bead; its fill comes within w/2 − overlap·w of the seam.
  double min_pass_x = 1e9, min_fill_x = 1e9;
  for (const Move* m : prints(shared)) {
    if (shared.sections[static_cast<std::size_t>(m->section)] != "b") continue;
    const double x = std::min(m->start.x(), m->end.x());
    if (m->feature == Feature::kBoundary) min_pass_x = std::min(min_pass_x, x);
    if (m->feature == Feature::kFill) min_fill_x = std::min(min_fill_x, x);
  }
  EXPECT_NEAR(min_pass_x, 400 - 0.1 * w, 0.05);
  EXPECT_NEAR(min_fill_x, 400 + 0.5 * w - 0.1 * w,
              0.5 * w * 0.9 + 0.05);  // fill lines meet the region's edge
  EXPECT_LT(min_fill_x, 400 + 0.5 * w);
  // Each of b's passes is one U-shaped bead per layer: 2 layers × 2 passes.
  int beads = 0;
  const Move* prev = nullptr;
  for (const Move* m : prints(shared, 0, Feature::kBoundary)) {
    if (!prev || (prev->end - m->start).norm() > 1e-6) ++beads;
    prev = m;
  }
  EXPECT_EQ(beads, 4);
  // Each layer: a's layer comes before b's at the same height.
  ASSERT_EQ(shared.layers.size(), 4u);
  EXPECT_EQ(shared.sections[static_cast<std::size_t>(shared.layers[0].section)], "a");
  EXPECT_EQ(shared.sections[static_cast<std::size_t>(shared.layers[1].section)], "b");
  // a itself is unchanged.
  EXPECT_NEAR(length(prints(shared, 1)), length(prints(own, 0)), 1e-6);

  SectionParams bad = b;
  bad.shares_wall_with = "nobody";
  EXPECT_THROW((void)plan_toolpath(touching_boxes(20), {a, bad}, {}), InputError);
  bad.shares_wall_with = "a";
  bad.layer_height_mm = 5;
  EXPECT_THROW((void)plan_toolpath(touching_boxes(20), {a, bad}, {}), InputError);
}

// Patent (41): containment boundaries cut the section's share out of the part.
TEST(SectionParams, ContainmentBoundariesLimitTheSection) {
  SectionParams s = section(10, 10, 20, 1);
  s.containment_outside = {rect(0, 0, 200, 300)};
  const Toolpath half = plan_toolpath(make_box({400, 300, 10}), {s}, {});
  ASSERT_EQ(half.layers.size(), 1u);
  EXPECT_NEAR(half.layers[0].outline_area_mm2, 200.0 * 300, 1e-3);
  for (const Move* m : prints(half)) EXPECT_LE(std::max(m->start.x(), m->end.x()), 200 - 10 + 1e-6);

  s.containment_outside.clear();
  s.containment_inside = {rect(150, 100, 250, 200)};
  const Toolpath holed = plan_toolpath(make_box({400, 300, 10}), {s}, {});
  EXPECT_NEAR(holed.layers[0].outline_area_mm2, 400.0 * 300 - 100 * 100, 1e-3);
  // A pass runs around the hole, half a bead from its edge.
  bool around_hole = false;
  for (const Move* m : prints(holed))
    around_hole |= std::abs(m->start.x() - 140) < 1e-6 && std::abs(m->end.x() - 140) < 1e-6;
  EXPECT_TRUE(around_hole);
}

// Patent (44): the slice plane lays the part down before it is sliced.
TEST(SectionParams, SlicePlaneChoosesTheLayerDirection) {
  const TriangleMesh box = make_box({100, 50, 20});
  SectionParams s = section(20, 5, 10, 1);
  EXPECT_EQ(plan_toolpath(box, {s}, {}).layers.size(), 4u);
  s.slice_plane = SlicePlane::kFront;  // +Y up: 50 mm tall, layers 100 x 20
  s.z_max_mm = 50;
  const Toolpath front = plan_toolpath(box, {s}, {});
  ASSERT_EQ(front.layers.size(), 10u);
  EXPECT_NEAR(front.layers[0].outline_area_mm2, 100.0 * 20, 1e-6);
  s.slice_plane = SlicePlane::kSide;  // +X up: 100 mm tall, layers 50 x 20
  s.z_max_mm = 100;
  const Toolpath side = plan_toolpath(box, {s}, {});
  ASSERT_EQ(side.layers.size(), 20u);
  EXPECT_NEAR(side.layers[0].outline_area_mm2, 50.0 * 20, 1e-6);
  // Laid down, the box keeps its footprint corner and is still a closed solid of the same volume.
  const TriangleMesh down = lay_down(box, SlicePlane::kFront);
  EXPECT_NEAR(down.volume_mm3(), box.volume_mm3(), 1e-6);
  EXPECT_NEAR((down.min_corner() - box.min_corner()).norm(), 0.0, 1e-9);
}

// Patent (45): stock and toolpath offsets combined (one sharp offset) or not (a constant-distance stock
// envelope, round at convex corners, then the passes).
TEST(SectionParams, CombineStockOffsetKeepsCornersSharp) {
  SectionParams s = section(10, 10, 10, 1);
  s.outer_stock_mm = 10;
  auto nearest_to_corner = [&](const Toolpath& tp) {
    double d = 1e9;
    for (const Move* m : prints(tp)) d = std::min(d, (m->end.head<2>() - Eigen::Vector2d(-5, -5)).norm());
    return d;
  };
  s.combine_stock_offset = true;
  EXPECT_LT(nearest_to_corner(plan_toolpath(make_box({200, 200, 10}), {s}, {})), 0.01);
  s.combine_stock_offset = false;
  // The envelope's corner is an arc of radius 10 about (0, 0); the pass 5 inside it, an arc of radius 5.
  EXPECT_NEAR(nearest_to_corner(plan_toolpath(make_box({200, 200, 10}), {s}, {})), std::sqrt(50.0) - 5, 0.15);
}

// Patent (47): never start in a corner moves the start onto a straight run, a bead width from any corner.
TEST(SectionParams, NeverStartInACorner) {
  SectionParams s = section(10, 10, 20, 1);
  s.start_point_mm = {0, 0};
  auto first_pass_start = [&] {
    const Toolpath tp = plan_toolpath(make_box({200, 200, 10}), {s}, {});
    return prints(tp, -1, Feature::kBoundary).front()->start.head<2>().eval();
  };
  EXPECT_NEAR((first_pass_start() - Eigen::Vector2d(10, 10)).norm(), 0.0, 1e-6);
  s.smoothing.never_start_in_corner = true;
  const Eigen::Vector2d p = first_pass_start();
  for (const Eigen::Vector2d& c : {Eigen::Vector2d(10, 10), Eigen::Vector2d(190, 10),
                                   Eigen::Vector2d(190, 190), Eigen::Vector2d(10, 190)})
    EXPECT_GE((p - c).norm(), 20 - 1e-6);
  EXPECT_LT((p - Eigen::Vector2d(10, 10)).norm(), 20 + 1e-6);  // the nearest allowed start, on along the pass
}

// Patent (47): minimum polygon angle cuts back pass corners sharper than it.
TEST(SectionParams, MinimumPolygonAngleBluntsSharpCorners) {
  // A triangle with a 70 degree apex at (100, 0) pointing in +x (containment cut from a box).
  const double half = 35.0 * kPi / 180.0;
  SectionParams s = section(10, 10, 10, 1);
  s.containment_outside = {
      {{100, 150}, {-200, 150 - 300 * std::tan(half)}, {-200, 150 + 300 * std::tan(half)}}};
  auto max_left_turn = [&] {
    const Toolpath tp = plan_toolpath(make_box({300, 300, 10}, {-200, 0, 0}), {s}, {});
    const auto moves = prints(tp, -1, Feature::kBoundary);
    double turn = 0;
    for (std::size_t i = 1; i < moves.size(); ++i) {
      const Eigen::Vector2d a = (moves[i - 1]->end - moves[i - 1]->start).head<2>();
      const Eigen::Vector2d b = (moves[i]->end - moves[i]->start).head<2>();
      turn = std::max(turn, std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b)) * 180 / kPi);
    }
    return turn;
  };
  EXPECT_NEAR(max_left_turn(), 110.0, 0.5);  // the apex: interior angle 70 degrees
  s.smoothing.min_polygon_angle_deg = 80;
  EXPECT_LT(max_left_turn(), 100.0);  // chamfered into two gentler turns
}

// Patent (47): corner pull-back lifts the roller `length` before each corner and drops it `extension` after.
TEST(SectionParams, CornerPullBackLiftsTheRollerAroundCorners) {
  SectionParams s = section(10, 10, 20, 1);
  s.start_point_mm = {100, 0};  // mid-edge: all four corners are inside the bead
  s.pull_back.length_mm = 30;
  s.pull_back.extension_mm = 15;
  const Toolpath tp = plan_toolpath(make_box({200, 200, 10}), {s}, {});
  double lifted = 0, down = 0, volume = 0;
  for (const Move* m : prints(tp)) {
    (m->roller_down ? down : lifted) += m->length_mm();
    volume += m->volume_mm3;
  }
  EXPECT_NEAR(lifted, 4 * (30.0 + 15.0), 1e-6);
  EXPECT_NEAR(lifted + down, 4 * 180.0, 1e-6);
  // Splitting moves keeps the material.
  s.pull_back = {};
  double plain = 0;
  const Toolpath without = plan_toolpath(make_box({200, 200, 10}), {s}, {});
  for (const Move* m : prints(without)) plain += m->volume_mm3;
  EXPECT_NEAR(volume, plain, 1e-6 * plain);
}

// Patent (50): the maximum pass overlap leaves a pass out where its two sides would overlap more.
// Patent (46): void detection finds what no bead covers and, when asked, lays a bead down it.
TEST(SectionParams, MaxPassOverlapAndVoidDetection) {
  // A strip 66 mm wide, w = 20, overlap 10 %: pass 0 centres 10 mm in, pass 1 28 mm in, so pass 1's two
  // long sides are 10 mm apart and overlap 50 %.
  SectionParams s = section(10, 10, 20, 2);
  const TriangleMesh strip = make_box({400, 66, 10});
  s.boundary.max_overlap = 0.6;
  const Toolpath kept = plan_toolpath(strip, {s}, {});
  s.boundary.max_overlap = 0.4;
  const Toolpath dropped = plan_toolpath(strip, {s}, {});
  const double outer = 2 * (380.0 + 46.0), inner = 2 * (344.0 + 10.0);
  EXPECT_NEAR(length(prints(kept)), outer + inner, 1e-6);
  EXPECT_NEAR(length(prints(dropped)), outer, 1e-6);

  // Without pass 1 a 26 mm strip is left between the pass-0 beads (y in [20, 46], x in [20, 380]).
  s.voids.detect = true;
  PlanStats stats;
  (void)plan_toolpath(strip, {s}, {}, &stats);
  EXPECT_EQ(stats.voids_found, 1);
  EXPECT_NEAR(stats.void_area_mm2, 360.0 * 26, 0.02 * 360 * 26);
  EXPECT_EQ(stats.void_beads, 0);
  s.voids.fill = true;
  const Toolpath filled = plan_toolpath(strip, {s}, {}, &stats);
  // 26 mm is wider than one bead (20 mm): two beads side by side, 13 mm each, centred 6.5 mm either side of
  // the void's middle (y = 33), along its length.
  EXPECT_EQ(stats.void_beads, 2);
  const auto extra = prints(filled, -1, Feature::kFill);
  ASSERT_FALSE(extra.empty());
  for (const Move* m : extra) {
    EXPECT_NEAR(std::abs(m->start.y() - 33.0), 6.5, 0.5);
    EXPECT_NEAR(m->bead_width_mm, 13.0, 0.5);
  }
  EXPECT_NEAR(length(extra), 2 * 360.0, 2.0);
  // With every pass kept, nothing is left uncovered.
  s.boundary.max_overlap = 1.0;
  (void)plan_toolpath(strip, {s}, {}, &stats);
  EXPECT_EQ(stats.voids_found, 0);
}

// Patent (47): maintain smooth curves puts points back where simplification would facet a curve.
TEST(SectionParams, SmoothCurvesKeepCurvesSmooth) {
  Polygon circle;
  for (int i = 0; i < 720; ++i)
    circle.emplace_back(100 * std::cos(i * kPi / 360), 100 * std::sin(i * kPi / 360));
  auto max_turn_deg = [](const Polygon& p) {
    double t = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Eigen::Vector2d a = p[i] - p[(i + p.size() - 1) % p.size()], b = p[(i + 1) % p.size()] - p[i];
      t = std::max(t, std::abs(std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b))) * 180 / kPi);
    }
    return t;
  };
  const Polygons coarse = simplify({circle}, 2.0);
  const Polygons smooth = simplify({circle}, 2.0, true);
  ASSERT_EQ(coarse.size(), 1u);
  ASSERT_EQ(smooth.size(), 1u);
  EXPECT_GT(max_turn_deg(coarse[0]), 20.0);
  EXPECT_LE(max_turn_deg(smooth[0]), kSmoothTurnDeg + 1e-9);
  EXPECT_LT(smooth[0].size(), circle.size() / 4);  // still a simplification
  // A square's corners are the part's own: they stay.
  Polygon square;
  for (int i = 0; i < 40; ++i) square.emplace_back(i * 5.0, 0);
  for (int i = 0; i < 40; ++i) square.emplace_back(200, i * 5.0);
  for (int i = 0; i < 40; ++i) square.emplace_back(200 - i * 5.0, 200);
  for (int i = 0; i < 40; ++i) square.emplace_back(0, 200 - i * 5.0);
  EXPECT_EQ(simplify({square}, 0.5, true)[0].size(), 4u);
}

// Patent (50) thin-wall parameters, on the beads laid down centre lines.
TEST(CentreBeads, OneBeadWidthSplitsWideWallsIntoTwoBeads) {
  CentreBeadRules r;
  r.min_width_mm = 1;
  r.max_width_mm = 20;
  r.one_bead_width_mm = 20;
  const Polygons strip = {rect(0, 0, 200, 16)};
  const auto one = centre_beads(strip, {}, r);
  ASSERT_EQ(one.size(), 1u);
  for (const auto& p : one[0].points) EXPECT_NEAR(p.y(), 8.0, 0.05);
  for (const double w : one[0].widths_mm) EXPECT_NEAR(w, 16.0, 0.1);
  // The line stops 8 mm short of the square ends; the bead runs on to them.
  EXPECT_NEAR(std::min(one[0].points.front().x(), one[0].points.back().x()), 0.0, 0.1);
  EXPECT_NEAR(std::max(one[0].points.front().x(), one[0].points.back().x()), 200.0, 0.1);
  r.one_bead_width_mm = 12;
  const auto two = centre_beads(strip, {}, r);
  ASSERT_EQ(two.size(), 2u);
  std::vector<double> ys;
  for (const auto& b : two) {
    for (const double w : b.widths_mm) EXPECT_NEAR(w, 8.0, 0.1);
    ys.push_back(b.points[b.points.size() / 2].y());
  }
  std::sort(ys.begin(), ys.end());
  EXPECT_NEAR(ys[0], 4.0, 0.05);
  EXPECT_NEAR(ys[1], 12.0, 0.05);
  // Wider than the maximum width: no bead at all.
  r.max_width_mm = 15;
  EXPECT_TRUE(centre_beads(strip, {}, r).empty());
}

TEST(CentreBeads, ThicknessDeviationHoldsTheWidthInSteps) {
  // A wedge 20 mm wide at x = 0 narrowing to 4 mm at x = 400.
  const Polygons wedge = {{{0, -10}, {400, -2}, {400, 2}, {0, 10}}};
  CentreBeadRules r;
  r.min_width_mm = 1;
  r.max_width_mm = 30;
  r.one_bead_width_mm = 30;
  auto widths = [&] {
    const auto beads = centre_beads(wedge, {}, r);
    EXPECT_EQ(beads.size(), 1u);
    std::vector<double> w = beads.empty() ? std::vector<double>{} : beads[0].widths_mm;
    std::sort(w.begin(), w.end());
    w.erase(std::unique(w.begin(), w.end(), [](double a, double b) { return std::abs(a - b) < 1e-9; }),
            w.end());
    return w;
  };
  EXPECT_GT(widths().size(), 8u);  // follows the wall
  r.thickness_deviation_mm = 4;
  const auto steps = widths();
  EXPECT_GE(steps.size(), 3u);  // 16 mm of taper in steps of at most 4 mm
  EXPECT_LE(steps.size(), 5u);
}

TEST(CentreBeads, StitchingGapAndIntersectionDistance) {
  // Two strips in line with a 5 mm gap between their ends once each bead runs on to its square end.
  const Polygons strips = {rect(0, 0, 100, 10), rect(105, 0, 205, 10)};
  CentreBeadRules r;
  r.min_width_mm = 1;
  r.max_width_mm = 20;
  r.one_bead_width_mm = 20;
  EXPECT_EQ(centre_beads(strips, {}, r).size(), 2u);
  r.stitching_gap_mm = 4;
  EXPECT_EQ(centre_beads(strips, {}, r).size(), 2u);
  r.stitching_gap_mm = 6;
  ASSERT_EQ(centre_beads(strips, {}, r).size(), 1u);
  // A free end reaches on up to the intersection distance to meet a pass's bead (here 10 mm beyond it).
  r.stitching_gap_mm = 0;
  const Polygons strip = {rect(0, 0, 100, 10)}, pass = {rect(110, -10, 150, 20)};
  auto reach = [&] {
    const auto beads = centre_beads(strip, pass, r);
    EXPECT_EQ(beads.size(), 1u);
    return std::max(beads[0].points.front().x(), beads[0].points.back().x());
  };
  EXPECT_NEAR(reach(), 100.0, 0.1);
  r.intersection_distance_mm = 15;
  EXPECT_NEAR(reach(), 110.0, 0.6);
  r.intersection_distance_mm = 5;  // too far to reach: the end stays
  EXPECT_NEAR(reach(), 100.0, 0.1);
}

}  // namespace
}  // namespace beadtwin::slicer
