#include <algorithm>
#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "core/bead.hpp"
#include "core/error.hpp"
#include "core/units.hpp"
#include "gcode/writer.hpp"
#include "slicer/mesh.hpp"
#include "slicer/plan.hpp"
#include "slicer/polygons.hpp"
#include "slicer/slice.hpp"

namespace beadtwin::slicer {
namespace {

SectionParams section(double z0, double z1, double h, double w, int passes, bool fill) {
  SectionParams s;
  s.name = "s";
  s.z_min_mm = z0;
  s.z_max_mm = z1;
  s.layer_height_mm = h;
  s.bead_width_mm = w;
  s.print_speed_mm_s = 50;
  s.travel_speed_mm_s = 200;
  s.boundary.passes = passes;
  s.fill.enabled = fill;
  return s;
}

TEST(Slice, BoxSliceIsItsFootprint) {
  const TriangleMesh box = make_box({100, 50, 20}, {10, 0, 0});
  const Polygons p = slice_mesh(box, 5.0);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_NEAR(area_mm2(p), 5000.0, 1e-6);  // positive: counter-clockwise outer contour
  EXPECT_TRUE(slice_mesh(box, 25.0).empty());
  // Exactly at a vertex plane, vertices count as above it: the top face's plane still cuts the sides once,
  // the bottom face's plane has nothing below it.
  EXPECT_NEAR(area_mm2(slice_mesh(box, 20.0)), 5000.0, 1e-6);
  EXPECT_TRUE(slice_mesh(box, 0.0).empty());
}

TEST(Slice, OpenBoxHasAHoleAboveTheFloor) {
  const TriangleMesh m = make_open_box({100, 80, 50}, 10, 5);
  EXPECT_NEAR(area_mm2(slice_mesh(m, 2.5)), 8000.0, 1e-6);
  const Polygons ring = slice_mesh(m, 20.0);
  EXPECT_EQ(ring.size(), 2u);
  EXPECT_NEAR(area_mm2(ring), 8000.0 - 80.0 * 60.0, 1e-6);
}

TEST(Plan, CubeIsSlicedIntoTheExpectedLayers) {
  // A 100 mm cube at 5 mm layers: 20 layers with tops at 5, 10, ... 100 mm.
  const TriangleMesh cube = make_box({100, 100, 100});
  const Toolpath tp = plan_toolpath(cube, {section(0, 100, 5, 20, 1, false)}, {});
  ASSERT_EQ(tp.layers.size(), 20u);
  for (std::size_t i = 0; i < tp.layers.size(); ++i)
    EXPECT_NEAR(tp.layers[i].z_mm, 5.0 * static_cast<double>(i + 1), 1e-9);
}

// An open box's floor (two passes and fill) and its 100 mm walls (`wall_passes` passes of 20 mm beads).
std::vector<SectionParams> floor_and_walls(int wall_passes) {
  std::vector<SectionParams> secs = {section(0, 10, 5, 20, 2, true),
                                     section(10, 60, 5, 20, wall_passes, false)};
  secs[0].name = "floor";
  secs[1].name = "walls";
  return secs;
}

TEST(Plan, TwoSectionsWithTheirOwnParameters) {
  const TriangleMesh m = make_open_box({400, 300, 60}, 100, 10);
  const std::vector<SectionParams> secs = floor_and_walls(3);
  PlanStats stats;
  const Toolpath tp = plan_toolpath(m, secs, {}, &stats);
  ASSERT_EQ(tp.layers.size(), 12u);
  EXPECT_EQ(tp.layers[0].section, 0);
  EXPECT_EQ(tp.layers[2].section, 1);
  EXPECT_EQ(stats.open_chains, 0);
  int max_pass_floor = -1, max_pass_walls = -1, fill_moves = 0;
  for (const Move& mv : tp.moves) {
    if (mv.feature == Feature::kBoundary)
      (mv.section == 0 ? max_pass_floor : max_pass_walls) =
          std::max(mv.section == 0 ? max_pass_floor : max_pass_walls, mv.pass);
    if (mv.feature == Feature::kFill) {
      ++fill_moves;
      EXPECT_EQ(mv.section, 0);
    }
  }
  EXPECT_EQ(max_pass_floor, 1);  // passes 0 and 1
  EXPECT_EQ(max_pass_walls, 2);  // passes 0, 1 and 2 fit on both contours of a 100 mm wall
  EXPECT_GT(fill_moves, 10);
}

TEST(Plan, SaysHowManyBoundaryPassesHadRoom) {
  // The 100 mm wall holds three 20 mm passes along each of its contours; asking for five lays the same three.
  PlanStats stats;
  (void)plan_toolpath(make_open_box({400, 300, 60}, 100, 10), floor_and_walls(5), {}, &stats);
  EXPECT_EQ(stats.most_passes_laid, (std::vector<int>{2, 3}));
}

TEST(Plan, BoundaryPassesSitAtTheirOffsets) {
  // Pass k of a square runs at w/2 + k * pitch inside the outline.
  const double w = 20, overlap = 0.1, pitch = w * (1 - overlap);
  SectionParams s = section(0, 5, 5, w, 3, false);
  s.boundary.overlap = overlap;
  const Toolpath tp = plan_toolpath(make_box({200, 200, 5}), {s}, {});
  double min_x[3] = {1e9, 1e9, 1e9};
  for (const Move& m : tp.moves)
    if (m.feature == Feature::kBoundary) min_x[m.pass] = std::min(min_x[m.pass], m.end.x());
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(min_x[k], w / 2 + k * pitch, 1e-3) << "pass " << k;
}

TEST(Plan, FillCoversTheInsideAndTurnsEachLayer) {
  const double w = 20, h = 5;
  SectionParams s = section(0, 10, h, w, 1, true);
  s.fill.angle_deg = 0;
  s.fill.angle_step_deg = 90;
  const Toolpath tp = plan_toolpath(make_box({300, 200, 10}), {s}, {});
  ASSERT_EQ(tp.layers.size(), 2u);
  // Commanded volume of a layer is close to the footprint times the layer height.
  for (std::size_t l = 0; l < 2; ++l) {
    double v = 0;
    for (std::size_t i = tp.layers[l].first_move; i < tp.layers[l].end_move; ++i) v += tp.moves[i].volume_mm3;
    EXPECT_NEAR(v / (300.0 * 200 * h), 1.0, 0.12) << "layer " << l;
  }
  // Fill direction: mostly along x on layer 0, along y on layer 1.
  double along[2][2] = {{0, 0}, {0, 0}};
  for (const Move& m : tp.moves)
    if (m.feature == Feature::kFill) {
      along[m.layer][0] += std::abs(m.end.x() - m.start.x());
      along[m.layer][1] += std::abs(m.end.y() - m.start.y());
    }
  EXPECT_GT(along[0][0], 5 * along[0][1]);
  EXPECT_GT(along[1][1], 5 * along[1][0]);
}

TEST(Plan, VolumeFollowsTheStadiumSection) {
  SectionParams s = section(0, 5, 5, 20, 1, false);
  const Toolpath tp = plan_toolpath(make_box({200, 100, 5}), {s}, {});
  EXPECT_NEAR(tp.commanded_volume_mm3(), tp.print_length_mm() * bead_area_mm2(20, 5), 1e-6);
  EXPECT_GT(tp.total_time_s(), tp.print_length_mm() / 50);
}

TEST(Plan, BadParametersAreInputErrors) {
  EXPECT_THROW((void)plan_toolpath(make_box({10, 10, 10}), {section(0, 10, 5, 4, 1, false)}, {}), InputError);
  EXPECT_THROW((void)plan_toolpath(make_box({10, 10, 10}), {section(0, 10, 0, 4, 1, false)}, {}), InputError);
}

TEST(Gcode, ProgramNamesLayersSectionsAndFeatures) {
  SectionParams s = section(0, 10, 5, 20, 2, true);
  s.name = "base";
  const Toolpath tp = plan_toolpath(make_box({200, 100, 10}), {s}, {});
  gcode::GcodeDialect d;
  d.inches = true;
  const std::string g = gcode::write_gcode(tp, d, {"T", "sc", "v", "m", "x"});
  EXPECT_NE(g.find("G20"), std::string::npos);
  EXPECT_NE(g.find("(LAYER 1 SECTION base Z 0.394"), std::string::npos) << g.substr(0, 600);
  EXPECT_NE(g.find("(BOUNDARY PASS 2)"), std::string::npos);
  EXPECT_NE(g.find("(fill)"), std::string::npos);
  EXPECT_NE(g.find("M23"), std::string::npos);
  EXPECT_NE(g.find("M30"), std::string::npos);
}

}  // namespace
}  // namespace beadtwin::slicer

namespace beadtwin::slicer {
namespace {

// The start of each layer's outer pass on a 200 mm square (pass centreline: a 180 mm square starting at
// (10, 10)), as arclength along the pass from its corner nearest the origin.
std::vector<Eigen::Vector3d> pass_starts(const Toolpath& tp) {
  std::vector<Eigen::Vector3d> starts;
  int layer = -1;
  for (const Move& m : tp.moves)
    if (m.feature == Feature::kBoundary && m.pass == 0 && m.layer != layer) {
      layer = m.layer;
      starts.push_back(m.start);
    }
  return starts;
}

TEST(Plan, SeamsAdvanceByTheSeamAvoidanceOffset) {
  SectionParams s = section(0, 25, 5, 20, 1, false);
  s.seam_offset_mm = 50;
  const Toolpath tp = plan_toolpath(make_box({200, 200, 25}), {s}, {});
  const auto starts = pass_starts(tp);
  ASSERT_EQ(starts.size(), 5u);
  // The pass runs counter-clockwise from (10, 10): +x first. Arclength 50 L along a 720 mm loop.
  const Eigen::Vector2d expected[5] = {{10, 10}, {60, 10}, {110, 10}, {160, 10}, {190, 30}};
  for (std::size_t l = 0; l < 5; ++l) {
    EXPECT_NEAR(starts[l].x(), expected[l].x(), 1e-6) << "layer " << l;
    EXPECT_NEAR(starts[l].y(), expected[l].y(), 1e-6) << "layer " << l;
  }
  // Without the offset every layer starts at the same place, nearest the start point.
  s.seam_offset_mm = 0;
  s.start_point_mm = {200, 120};
  for (const auto& p : pass_starts(plan_toolpath(make_box({200, 200, 25}), {s}, {}))) {
    EXPECT_NEAR(p.x(), 190, 1e-6);
    EXPECT_NEAR(p.y(), 120, 1e-6);
  }
}

// Signed area swept by the outer pass of each layer: positive counter-clockwise.
std::vector<double> pass_orientation(const Toolpath& tp) {
  std::vector<double> area(tp.layers.size(), 0.0);
  for (const Move& m : tp.moves)
    if (m.feature == Feature::kBoundary && m.pass == 0)
      area[static_cast<std::size_t>(m.layer)] += m.start.x() * m.end.y() - m.end.x() * m.start.y();
  return area;
}

TEST(Plan, AlternatingLayersReverseDirection) {
  SectionParams s = section(0, 20, 5, 20, 2, false);
  const auto same = pass_orientation(plan_toolpath(make_box({200, 100, 20}), {s}, {}));
  for (double a : same) EXPECT_GT(a, 0);
  s.boundary.reverse_alternate = true;
  const auto alt = pass_orientation(plan_toolpath(make_box({200, 100, 20}), {s}, {}));
  ASSERT_EQ(alt.size(), 4u);
  for (std::size_t l = 0; l < alt.size(); ++l) EXPECT_EQ(alt[l] > 0, l % 2 == 0) << "layer " << l;
}

TEST(Plan, InsideOutLaysTheInnermostPassFirst) {
  SectionParams s = section(0, 5, 5, 20, 3, false);
  s.boundary.inside_out = true;
  const Toolpath tp = plan_toolpath(make_box({200, 200, 5}), {s}, {});
  std::vector<int> order;
  for (const Move& m : tp.moves)
    if (m.feature == Feature::kBoundary && (order.empty() || order.back() != m.pass)) order.push_back(m.pass);
  EXPECT_EQ(order, (std::vector<int>{2, 1, 0}));
}

TEST(Plan, LeadInAndLeadOutHaveTheirLengths) {
  SectionParams s = section(0, 10, 5, 20, 2, false);
  s.boundary.lead_in_mm = 30;
  s.boundary.lead_out_mm = 45;
  const Toolpath tp = plan_toolpath(make_box({300, 200, 10}), {s}, {});
  int lead_ins = 0, lead_outs = 0;
  for (std::size_t i = 0; i < tp.moves.size(); ++i) {
    const Move& m = tp.moves[i];
    if (m.feature == Feature::kLeadIn) {
      ++lead_ins;
      EXPECT_NEAR(m.length_mm(), 30, 1e-6);
      EXPECT_GT(m.volume_mm3, 0);
      EXPECT_EQ(tp.moves[i + 1].feature, Feature::kBoundary);  // it leads into the pass
      EXPECT_NEAR((tp.moves[i + 1].start - m.end).norm(), 0, 1e-9);
    }
    if (m.feature == Feature::kLeadOut) {
      ++lead_outs;
      EXPECT_NEAR(m.length_mm(), 45, 1e-6);
      // Tangent to the pass's last segment.
      const Move& last = tp.moves[i - 1];
      EXPECT_NEAR((m.end - m.start).normalized().dot((last.end - last.start).normalized()), 1.0, 1e-9);
    }
  }
  EXPECT_EQ(lead_ins, 4);  // two passes on each of two layers
  EXPECT_EQ(lead_outs, 4);
}

}  // namespace
}  // namespace beadtwin::slicer

namespace beadtwin::slicer {
namespace {

// A square frustum: `bottom` wide at z = 0, `top` wide at z = height, centred on (0, 0).
TriangleMesh frustum(double bottom, double top, double height) {
  TriangleMesh m;
  const double b = bottom / 2, t = top / 2;
  m.vertices = {{-b, -b, 0},      {b, -b, 0},      {b, b, 0},      {-b, b, 0},
                {-t, -t, height}, {t, -t, height}, {t, t, height}, {-t, t, height}};
  m.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                 {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  return m;
}

double min_x_of(const Toolpath& tp, Feature f, int pass, int layer = -1) {
  double x = 1e18;
  for (const Move& m : tp.moves)
    if (m.feature == f && m.pass == pass && (layer < 0 || m.layer == layer))
      x = std::min({x, m.start.x(), m.end.x()});
  return x;
}

TEST(Plan, StockToLeaveOffsetsTheOutline) {
  // Outer stock moves the outer pass out; inner stock moves the hole's pass in (away from the wall).
  const TriangleMesh ring = make_open_box({300, 300, 20}, 80, 5, {-150, -150, 0});
  SectionParams s = section(5, 10, 5, 20, 1, false);
  const double plain = min_x_of(plan_toolpath(ring, {s}, {}), Feature::kBoundary, 0);
  EXPECT_NEAR(plain, -150 + 10, 1e-3);
  s.outer_stock_mm = 6;
  s.inner_stock_mm = 4;
  const Toolpath tp = plan_toolpath(ring, {s}, {});
  EXPECT_NEAR(min_x_of(tp, Feature::kBoundary, 0), -150 - 6 + 10, 1e-3);
  // The hole's pass: the hole spans x in [-70, 70]; its pass sits w/2 inside the wall, i.e. at |x| = 80,
  // and with inner stock at |x| = 70 + 4 + 10... the hole shrinks, so the pass moves toward the centre.
  double hole_pass = -1e18;
  for (const Move& m : tp.moves)
    if (m.feature == Feature::kBoundary && m.start.x() < 0 && std::abs(m.start.y()) < 40)
      hole_pass = std::max(hole_pass, m.start.x());
  EXPECT_NEAR(hole_pass, -70 + 4 - 10, 1e-3);
}

TEST(Plan, MergeSlicesTakesTheLargestNeighbouringOutline) {
  // A frustum narrowing upward: each layer's largest neighbour is the one below it.
  const TriangleMesh f = frustum(200, 100, 50);
  SectionParams s = section(0, 50, 5, 10, 1, false);
  const Toolpath plain = plan_toolpath(f, {s}, {});
  s.merge_slices = true;
  const Toolpath merged = plan_toolpath(f, {s}, {});
  ASSERT_EQ(plain.layers.size(), merged.layers.size());
  for (std::size_t l = 1; l < plain.layers.size(); ++l)
    EXPECT_NEAR(merged.layers[l].outline_area_mm2, plain.layers[l - 1].outline_area_mm2, 1e-3)
        << "layer " << l;
  // Below the first layer there is nothing: it keeps its own outline.
  EXPECT_NEAR(merged.layers[0].outline_area_mm2, plain.layers[0].outline_area_mm2, 1e-3);
}

TEST(Plan, IgnoreInnerContoursPrintsTheOutlineSolid) {
  const TriangleMesh ring = make_open_box({300, 300, 20}, 80, 5);
  SectionParams s = section(5, 10, 5, 20, 1, false);
  EXPECT_NEAR(plan_toolpath(ring, {s}, {}).layers[0].outline_area_mm2, 300.0 * 300 - 140.0 * 140, 1e-3);
  s.ignore_inner_contours = true;
  EXPECT_NEAR(plan_toolpath(ring, {s}, {}).layers[0].outline_area_mm2, 300.0 * 300, 1e-3);
}

TEST(Plan, LayerOrderPutsFillOrBoundaryFirst) {
  SectionParams s = section(0, 5, 5, 20, 1, true);
  auto first_print = [&] {
    for (const Move& m : plan_toolpath(make_box({200, 200, 5}), {s}, {}).moves)
      if (m.kind == MoveKind::kPrint) return m.feature;
    return Feature::kUnknown;
  };
  EXPECT_EQ(first_print(), Feature::kBoundary);
  s.fill_first = true;
  EXPECT_EQ(first_print(), Feature::kFill);
}

TEST(Plan, StartStopOverlapAndMinimumPassLength) {
  SectionParams s = section(0, 5, 5, 20, 1, false);
  auto boundary_length = [&](const TriangleMesh& m) {
    double l = 0;
    for (const Move& mv : plan_toolpath(m, {s}, {}).moves)
      if (mv.feature == Feature::kBoundary) l += mv.length_mm();
    return l;
  };
  const double loop = 4 * 180.0;  // pass 0 of a 200 mm square
  EXPECT_NEAR(boundary_length(make_box({200, 200, 5})), loop, 1e-6);
  s.boundary.start_stop_overlap = 0.5;  // half a bead width past the start
  EXPECT_NEAR(boundary_length(make_box({200, 200, 5})), loop + 10, 1e-6);
  s.boundary.min_pass_length_mm = loop + 1;
  EXPECT_EQ(boundary_length(make_box({200, 200, 5})), 0.0);
}

TEST(Plan, RaftsLiftThePartAndStockOnTopCaps) {
  SectionParams s = section(0, 20, 5, 20, 1, false);
  s.rafts = 2;
  s.stock_on_top = 3;
  const Toolpath tp = plan_toolpath(make_box({200, 200, 20}), {s}, {});
  ASSERT_EQ(tp.layers.size(), 2u + 4u + 3u);
  for (std::size_t l = 0; l < tp.layers.size(); ++l)
    EXPECT_NEAR(tp.layers[l].z_mm, 5.0 * static_cast<double>(l + 1), 1e-9);
  int raft_layers = 0, top_layers = 0, part_fill = 0;
  std::set<int> raft, top;
  for (const Move& m : tp.moves) {
    if (m.feature == Feature::kRaft) raft.insert(m.layer);
    if (m.feature == Feature::kStockOnTop) top.insert(m.layer);
    if (m.feature == Feature::kFill) ++part_fill;
  }
  raft_layers = static_cast<int>(raft.size());
  top_layers = static_cast<int>(top.size());
  EXPECT_EQ(raft_layers, 2);
  EXPECT_EQ(*raft.rbegin(), 1);
  EXPECT_EQ(top_layers, 3);
  EXPECT_EQ(*top.begin(), 6);
  EXPECT_EQ(part_fill, 0);  // the part's own layers have no fill; rafts and stock on top are solid
  // Rafts go under the lowest section only.
  SectionParams upper = section(20, 30, 5, 20, 1, false);
  upper.rafts = 1;
  EXPECT_THROW((void)plan_toolpath(make_box({200, 200, 30}), {section(0, 20, 5, 20, 1, false), upper}, {}),
               InputError);
}

TEST(Plan, ClearanceHeightBetweenLayers) {
  SectionParams s = section(0, 15, 5, 20, 1, false);
  s.clearance_height_mm = 100;
  s.seam_offset_mm = 50;  // so each layer starts elsewhere and the head crosses over at the clearance height
  const Toolpath tp = plan_toolpath(make_box({200, 200, 15}), {s}, {});
  int lifts = 0;
  for (const Move& m : tp.moves)
    if (m.kind == MoveKind::kTravel && m.end.z() == 100.0) ++lifts;
  EXPECT_EQ(lifts, 4);  // up after layers 0 and 1, and across at that height before layers 1 and 2
  for (const Move& m : tp.moves) {  // never a diagonal plunge
    if (m.kind == MoveKind::kTravel && m.start.z() == 100.0 && m.end.z() < 100.0) {
      EXPECT_NEAR((m.end - m.start).head<2>().norm(), 0.0, 1e-9);
    }
  }
}

}  // namespace
}  // namespace beadtwin::slicer

namespace beadtwin::slicer {
namespace {

TEST(Mesh, TieredOpenBoxThinsFromTheInside) {
  // 300 x 200 x 30 with a 10 mm floor; walls 40 mm up to z = 20, then 20 mm.
  const TriangleMesh m = make_open_box({300, 200, 30}, {{20, 40}, {30, 20}}, 10);
  const double cavity_low = 220.0 * 120 * 10, cavity_high = 260.0 * 160 * 10;
  EXPECT_NEAR(m.volume_mm3(), 300.0 * 200 * 30 - cavity_low - cavity_high, 1e-6);
  EXPECT_NEAR(area_mm2(slice_mesh(m, 15)), 300.0 * 200 - 220.0 * 120, 1e-6);
  EXPECT_NEAR(area_mm2(slice_mesh(m, 25)), 300.0 * 200 - 260.0 * 160, 1e-6);
  // A thicker wall above (an overhang into the cavity) is a valid solid too.
  const TriangleMesh over = make_open_box({300, 200, 30}, {{20, 20}, {30, 40}}, 10);
  EXPECT_NEAR(over.volume_mm3(), 300.0 * 200 * 30 - 260.0 * 160 * 10 - 220.0 * 120 * 10, 1e-6);
}

}  // namespace
}  // namespace beadtwin::slicer

namespace beadtwin::slicer {
namespace {

// Two bodies side by side: "a" at x in [0, 100], "b" at x in [200, 300] from z = b_bottom to b_top.
TriangleMesh two_bodies(double a_top, double b_bottom, double b_top) {
  TriangleMesh a = make_box({100, 100, a_top});
  const TriangleMesh b = make_box({100, 100, b_top - b_bottom}, {200, 0, b_bottom});
  const int base = static_cast<int>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (auto t : b.triangles) a.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  a.body.assign(a.triangles.size(), 0);
  std::fill(a.body.begin() + static_cast<std::ptrdiff_t>(b.triangles.size()), a.body.end(), 1);
  a.body_names = {"a", "b"};
  return a;
}

std::vector<std::pair<double, int>> layer_sequence(const Toolpath& tp) {
  std::vector<std::pair<double, int>> seq;
  for (const auto& l : tp.layers) seq.emplace_back(l.z_mm, l.section);
  return seq;
}

TEST(Plan, SectionsOnBodiesMergeByHeight) {
  // "AM Z merge": section 0 on body a at 5 mm layers, section 1 on body b at 10 mm layers, one program in
  // order of height; at equal heights the sections keep their order.
  SectionParams a = section(0, 20, 5, 20, 1, false), b = section(0, 20, 10, 20, 1, false);
  a.name = "a";
  a.body = "a";
  b.name = "b";
  b.body = "b";
  const Toolpath tp = plan_toolpath(two_bodies(20, 0, 20), {a, b}, {});
  const std::vector<std::pair<double, int>> expected = {{5, 0}, {10, 0}, {10, 1}, {15, 0}, {20, 0}, {20, 1}};
  EXPECT_EQ(layer_sequence(tp), expected);
  // Each section printed only its own body.
  for (const Move& m : tp.moves) {
    if (m.kind != MoveKind::kPrint) continue;
    EXPECT_EQ(m.section == 0, m.end.x() < 150.0)
        << "a move of section " << m.section << " at x = " << m.end.x();
  }
  SectionParams missing = a;
  missing.body = "c";
  EXPECT_THROW((void)plan_toolpath(two_bodies(20, 0, 20), {missing}, {}), InputError);
}

TEST(Plan, ElevatedSectionWaitsForTheBuildToReachIt) {
  // Body b starts 20 mm above the table (patent (16)): its first layer comes after body a's layer at 20 mm.
  SectionParams a = section(0, 40, 5, 20, 1, false), b = section(20, 40, 5, 20, 1, false);
  a.body = "a";
  b.body = "b";
  const Toolpath tp = plan_toolpath(two_bodies(40, 20, 40), {a, b}, {});
  const auto seq = layer_sequence(tp);
  ASSERT_EQ(seq.size(), 8u + 4u);
  const auto first_b = std::find_if(seq.begin(), seq.end(), [](const auto& p) { return p.second == 1; });
  ASSERT_NE(first_b, seq.end());
  EXPECT_DOUBLE_EQ(first_b->first, 25.0);
  EXPECT_EQ(std::prev(first_b)->first, 25.0);  // a's layer at 25 mm just before, at the same height
  EXPECT_EQ(std::count_if(seq.begin(), first_b, [](const auto& p) { return p.second == 0; }), 5);
}

}  // namespace
}  // namespace beadtwin::slicer

namespace beadtwin::slicer {
namespace {

// AM Outline (patent (39)): the section prints its 2-D path itself, layer after layer.
TEST(Plan, OutlineSectionPrintsItsPath) {
  SectionParams s = section(0, 15, 5, 20, 1, false);
  s.outline_path = {{0, 0}, {300, 0}, {300, 100}, {0, 100}};
  const Toolpath tp = plan_toolpath(TriangleMesh{}, {s}, {});
  ASSERT_EQ(tp.layers.size(), 3u);
  std::vector<double> printed(3, 0.0);
  for (const Move& m : tp.moves)
    if (m.kind == MoveKind::kPrint) printed[static_cast<std::size_t>(m.layer)] += m.length_mm();
  for (double l : printed) EXPECT_NEAR(l, 800.0, 1e-9);  // the path itself: no offset
  EXPECT_NEAR(tp.moves[1].start.x(), 0.0, 1e-9);         // starts at the point nearest the start point
  // Open, with a lead-in.
  s.outline_closed = false;
  s.boundary.lead_in_mm = 25;
  const Toolpath open = plan_toolpath(TriangleMesh{}, {s}, {});
  double lead = 0, body = 0;
  for (const Move& m : open.moves) {
    if (m.layer != 0 || m.kind != MoveKind::kPrint) continue;
    (m.feature == Feature::kLeadIn ? lead : body) += m.length_mm();
  }
  EXPECT_NEAR(lead, 25, 1e-9);
  EXPECT_NEAR(body, 700, 1e-9);  // three sides (300 + 100 + 300), not back to the start
}

}  // namespace
}  // namespace beadtwin::slicer

namespace beadtwin::slicer {
namespace {

TEST(Plan, LeadOutAlongThePassWhenNotTangential) {
  SectionParams s = section(0, 5, 5, 20, 1, false);
  s.boundary.lead_out_mm = 45;
  s.boundary.start_stop_overlap = 0.5;  // 10 mm
  s.boundary.tangential_lead_out = false;
  const Toolpath tp = plan_toolpath(make_box({200, 200, 5}), {s}, {});
  double boundary = 0, lead_out = 0;
  for (const Move& m : tp.moves) {
    if (m.feature == Feature::kBoundary) boundary += m.length_mm();
    if (m.feature == Feature::kLeadOut) {
      lead_out += m.length_mm();
      EXPECT_NEAR(m.end.y(), 10.0, 1e-9);  // on along the pass's first side (y = 10), not off it
    }
  }
  EXPECT_NEAR(boundary, 720 + 10, 1e-9);
  EXPECT_NEAR(lead_out, 45, 1e-9);
}

}  // namespace
}  // namespace beadtwin::slicer

namespace beadtwin::slicer {
namespace {

TEST(Polygons, ChordToleranceSimplifiesWithinTheTolerance) {
  Polygon circle;
  for (int i = 0; i < 720; ++i)
    circle.emplace_back(100 * std::cos(i * kPi / 360), 100 * std::sin(i * kPi / 360));
  const Polygons simple = simplify({circle}, 0.5);
  ASSERT_EQ(simple.size(), 1u);
  EXPECT_LT(simple[0].size(), 60u);
  EXPECT_GT(simple[0].size(), 10u);
  // Every original point stays within the tolerance of the simplified contour.
  for (const auto& p : circle) {
    double d = 1e9;
    for (std::size_t i = 0; i < simple[0].size(); ++i) {
      const Eigen::Vector2d a = simple[0][i], b = simple[0][(i + 1) % simple[0].size()];
      const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      d = std::min(d, (a + t * (b - a) - p).norm());
    }
    EXPECT_LE(d, 0.5 + 1e-9);
  }
  EXPECT_EQ(simplify({circle}, 0.0)[0].size(), circle.size());
}

TEST(Plan, SmallPolygonsAndContactOffset) {
  // A 200 mm square with a 10 mm island beside it: the island is left out when below the minimum area.
  TriangleMesh m = make_box({200, 200, 10});
  const TriangleMesh island = make_box({10, 10, 10}, {250, 0, 0});
  const int base = static_cast<int>(m.vertices.size());
  m.vertices.insert(m.vertices.end(), island.vertices.begin(), island.vertices.end());
  for (auto t : island.triangles) m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  m.body.assign(m.triangles.size(), 0);
  SectionParams s = section(0, 10, 5, 8, 1, false);
  EXPECT_NEAR(plan_toolpath(m, {s}, {}).layers[0].outline_area_mm2, 40000 + 100, 1e-6);
  s.min_polygon_area_mm2 = 500;
  EXPECT_NEAR(plan_toolpath(m, {s}, {}).layers[0].outline_area_mm2, 40000, 1e-6);
  // Contact tip-workpiece: a section whose limits start at 20 mm prints on the table with -20 mm.
  SectionParams upper = section(20, 40, 5, 20, 1, false);
  upper.contact_offset_mm = -20;
  const Toolpath tp = plan_toolpath(make_box({200, 200, 40}), {upper}, {});
  ASSERT_EQ(tp.layers.size(), 4u);
  EXPECT_DOUBLE_EQ(tp.layers[0].z_mm, 5.0);
}

}  // namespace
}  // namespace beadtwin::slicer

namespace beadtwin::slicer {
namespace {

TEST(Plan, MeltSettingSlowsThePumpWhereABeadRetracesAnother) {
  SectionParams s = section(0, 5, 5, 20, 1, false);
  s.boundary.start_stop_overlap = 1.0;  // 20 mm laid over the start
  s.melt_reduction = 0.4;
  const Toolpath tp = plan_toolpath(make_box({200, 200, 5}), {s}, {});
  const double area = bead_area_mm2(20, 5);
  double full = 0, reduced = 0;
  for (const Move& m : tp.moves) {
    if (m.kind != MoveKind::kPrint) continue;
    if (std::abs(m.volume_mm3 - area * m.length_mm()) < 1e-6)
      full += m.length_mm();
    else if (std::abs(m.volume_mm3 - 0.6 * area * m.length_mm()) < 1e-6)
      reduced += m.length_mm();
    else
      ADD_FAILURE() << "volume " << m.volume_mm3 << " for " << m.length_mm() << " mm";
  }
  EXPECT_NEAR(full, 720, 1e-9);
  EXPECT_NEAR(reduced, 20, 1e-9);
}

}  // namespace
}  // namespace beadtwin::slicer

namespace beadtwin::slicer {
namespace {

// A prism of a convex polygon (counter-clockwise), `height` tall.
TriangleMesh prism(const std::vector<Eigen::Vector2d>& poly, double height) {
  TriangleMesh m;
  const int n = static_cast<int>(poly.size());
  for (const auto& p : poly) m.vertices.emplace_back(p.x(), p.y(), 0.0);
  for (const auto& p : poly) m.vertices.emplace_back(p.x(), p.y(), height);
  for (int i = 1; i + 1 < n; ++i) {
    m.triangles.push_back({0, i + 1, i});          // bottom, facing down
    m.triangles.push_back({n, n + i, n + i + 1});  // top, facing up
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    m.triangles.push_back({i, j, n + j});
    m.triangles.push_back({i, n + j, n + i});
  }
  m.body.assign(m.triangles.size(), 0);
  return m;
}

TEST(Plan, ThinWallOnATaperedWallGetsOneCentreBead) {
  // 40 mm wide at x = 0 tapering to 10 mm at x = 300; with a 20 mm bead, one pass reaches only where the
  // wall is wider than 20 mm (x < 200); beyond that is a thin wall.
  const TriangleMesh wedge = prism({{0, -20}, {300, -5}, {300, 5}, {0, 20}}, 5);
  SectionParams s = section(0, 5, 5, 20, 1, false);
  auto thin_moves = [&] {
    std::vector<Move> out;
    for (const Move& m : plan_toolpath(wedge, {s}, {}).moves)
      if (m.feature == Feature::kThinWall) out.push_back(m);
    return out;
  };
  EXPECT_TRUE(thin_moves().empty());  // off by default
  s.boundary.thin_walls = true;
  const auto thin = thin_moves();
  ASSERT_FALSE(thin.empty());
  double x_min = 1e9, x_max = -1e9, last_width = 1e9;
  for (const Move& m : thin) {
    EXPECT_NEAR(m.start.y(), 0.0, 0.5);  // down the centre line
    EXPECT_NEAR(m.end.y(), 0.0, 0.5);
    x_min = std::min({x_min, m.start.x(), m.end.x()});
    x_max = std::max({x_max, m.start.x(), m.end.x()});
    // The wall's own width there: 40 − 30·x/300 mm at the move's middle, between 10 and 20 mm.
    const double x_mid = 0.5 * (m.start.x() + m.end.x());
    EXPECT_NEAR(m.bead_width_mm, 40.0 - 30.0 * x_mid / 300.0, 0.5);
    EXPECT_LE(m.bead_width_mm, last_width + 1e-9);  // narrowing towards the tip
    last_width = m.bead_width_mm;
    EXPECT_NEAR(m.volume_mm3, bead_area_mm2(m.bead_width_mm, 5) * m.length_mm(), 1e-6);
  }
  // From inside the pass's reach (its mitred tip runs to about x = 220 on the centre line)...
  EXPECT_GT(x_min, 195.0);
  EXPECT_LT(x_min, 215.0);
  EXPECT_NEAR(x_max, 300.0, 0.5);  // ...out to the wall's tip
  // A limit below the wall's width leaves it alone.
  s.boundary.thin_wall_max_width_mm = 8;
  EXPECT_TRUE(thin_moves().empty());
}

}  // namespace
}  // namespace beadtwin::slicer

namespace beadtwin::slicer {
namespace {

TEST(Plan, InitialClearanceAndOpenPathStart) {
  SectionParams s = section(0, 10, 5, 20, 1, false);
  s.initial_clearance_height_mm = 300;
  s.outline_path = {{0, 0}, {400, 0}};
  s.outline_closed = false;
  s.start_point_mm = {500, 0};  // nearer the far end: the open path runs from (400, 0)
  const Toolpath tp = plan_toolpath(TriangleMesh{}, {s}, {});
  ASSERT_FALSE(tp.moves.empty());
  EXPECT_DOUBLE_EQ(tp.moves.front().start.z(), 300.0);  // the program starts at the initial clearance height
  for (const Move& m : tp.moves) {
    if (m.kind != MoveKind::kPrint) continue;
    EXPECT_DOUBLE_EQ(m.start.x(), 400.0);
    EXPECT_DOUBLE_EQ(m.end.x(), 0.0);
    break;
  }
}

}  // namespace
}  // namespace beadtwin::slicer

namespace beadtwin::slicer {
namespace {

TEST(Plan, PassOverlapMeasuredBetweenAdjacentPasses) {
  // Adjacent passes overlap by `overlap` of the bead width: their centre lines are w (1 − overlap) apart.
  for (const double overlap : {0.0, 0.05, 0.2}) {
    SectionParams s = section(0, 5, 5, 20, 3, false);
    s.boundary.overlap = overlap;
    const Toolpath tp = plan_toolpath(make_box({300, 300, 5}), {s}, {});
    std::vector<double> x(3, 1e9);  // each pass's left side (its smallest x)
    for (const Move& m : tp.moves)
      if (m.feature == Feature::kBoundary) x[m.pass] = std::min({x[m.pass], m.start.x(), m.end.x()});
    for (int k = 0; k + 1 < 3; ++k) {
      const double pitch = x[k + 1] - x[k];
      EXPECT_NEAR((20 - pitch) / 20, overlap, 1e-6) << "passes " << k << " and " << k + 1;
    }
  }
}

}  // namespace
}  // namespace beadtwin::slicer

namespace beadtwin::slicer {
namespace {

TEST(Plan, SectionShiftMovesItsBeadsToOverlapItsNeighbour) {
  // Body b printed 3 mm toward body a so their beads overlap where the sections fuse.
  SectionParams a = section(0, 20, 5, 20, 1, false), b = section(0, 20, 5, 20, 1, false);
  a.body = "a";
  b.body = "b";
  b.shift_mm = {-3, 0};
  const Toolpath tp = plan_toolpath(two_bodies(20, 0, 20), {a, b}, {});
  double b_min = 1e18, a_min = 1e18;
  for (const Move& m : tp.moves) {
    if (m.kind != MoveKind::kPrint) continue;
    (m.section == 1 ? b_min : a_min) =
        std::min(m.section == 1 ? b_min : a_min, std::min(m.start.x(), m.end.x()));
  }
  EXPECT_NEAR(b_min, 200 + 10 - 3, 1e-6);
  EXPECT_NEAR(a_min, 10, 1e-6);  // the other section stays put
}

}  // namespace
}  // namespace beadtwin::slicer
