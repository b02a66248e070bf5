// The fill as the planner lays it (patent (51)-(65)): styles around a hole, boundary and side overlaps,
// corners, lead-in/out, rapids, sparse surfaces, variable bead regions and melt events. Each test fails if
// its parameter were ignored.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "core/bead.hpp"
#include "core/error.hpp"
#include "core/flow.hpp"
#include "core/units.hpp"
#include "slicer/mesh.hpp"
#include "slicer/plan.hpp"

namespace beadtwin::slicer {
namespace {

SectionParams plate(double height = 10, double h = 10) {
  SectionParams s;
  s.name = "plate";
  s.z_max_mm = height;
  s.layer_height_mm = h;
  s.bead_width_mm = 20;
  s.print_speed_mm_s = 50;
  s.travel_speed_mm_s = 200;
  s.boundary.passes = 1;
  s.boundary.overlap = 0.1;
  s.fill.enabled = true;
  s.fill.angle_deg = 0;
  s.fill.angle_step_deg = 0;
  return s;
}

std::vector<const Move*> moves(const Toolpath& tp, Feature f) {
  std::vector<const Move*> out;
  for (const Move& m : tp.moves)
    if (m.kind == MoveKind::kPrint && m.feature == f) out.push_back(&m);
  return out;
}

int melt_ons(const Toolpath& tp) {
  return static_cast<int>(std::count_if(tp.moves.begin(), tp.moves.end(),
                                        [](const Move& m) { return m.event == ExtruderEvent::kMeltOn; }));
}

// Every style keeps its beads out of the hole (patent FIGS. 15-19): no fill bead's edge enters it.
TEST(Fill, NoStylePrintsOverTheHole) {
  const TriangleMesh box = make_box({600, 400, 10});
  for (const FillStyleKind style : {FillStyleKind::kOneWay, FillStyleKind::kSimpleZigzag,
                                    FillStyleKind::kSmartZigzag, FillStyleKind::kSmartZigzagConstantOverlap,
                                    FillStyleKind::kSparseZigzag, FillStyleKind::kVariableBeadRegions}) {
    SectionParams s = plate();
    s.containment_inside = {{{300, 150}, {450, 150}, {450, 270}, {300, 270}}};
    s.fill.style = style;
    const Toolpath tp = plan_toolpath(box, {s}, {});
    int fill_moves = 0;
    for (const Move* m : moves(tp, Feature::kFill)) {
      ++fill_moves;
      for (int k = 0; k <= 8; ++k) {
        const Eigen::Vector3d p = m->start + (m->end - m->start) * (k / 8.0);
        // Distance from the point to the hole rectangle, outside it.
        const double dx = std::max({300 - p.x(), 0.0, p.x() - 450}),
                     dy = std::max({150 - p.y(), 0.0, p.y() - 270});
        EXPECT_GE(std::hypot(dx, dy), 0.5 * m->bead_width_mm - 1e-6)
            << "style " << static_cast<int>(style) << " at " << p.transpose();
      }
    }
    EXPECT_GT(fill_moves, 10) << static_cast<int>(style);
  }
}

// Patent (63): pass ends reach into the boundary beads by the boundary overlap (capped by the max end
// overlap distance, or as far as it allows when optimising to the surface); the passes beside the boundary
// overlap it by the boundary side overlap.
TEST(Fill, BoundaryAndSideOverlaps) {
  const TriangleMesh box = make_box({400, 300, 10});
  SectionParams s = plate();
  s.fill.style = FillStyleKind::kSmartZigzagConstantOverlap;  // lines on the region's edges
  s.fill.link_with_rapids = true;                             // every pass end is free
  s.fill.boundary_overlap = 0.25;
  s.fill.boundary_side_overlap = 0.2;
  auto extent = [&] {
    double x_min = 1e9, y_min = 1e9;
    const Toolpath tp = plan_toolpath(box, {s}, {});
    for (const Move* m : moves(tp, Feature::kFill)) {
      x_min = std::min({x_min, m->start.x(), m->end.x()});
      y_min = std::min({y_min, m->start.y(), m->end.y()});
    }
    return std::pair{x_min, y_min};
  };
  // The boundary bead's inner edge is at 20 mm.
  auto [x, y] = extent();
  EXPECT_NEAR(x, 20 - 0.25 * 20, 1e-3);
  EXPECT_NEAR(y, 20 + 10 - 0.2 * 20, 1e-3);
  s.fill.max_end_overlap_mm = 2;
  s.fill.max_side_overlap_mm = 1;
  std::tie(x, y) = extent();
  EXPECT_NEAR(x, 20 - 2, 1e-3);
  EXPECT_NEAR(y, 20 + 10 - 1, 1e-3);
  s.fill.max_end_overlap_mm = 0;
  s.fill.optimize_to_surface = true;  // as far as allowed: a whole bead width without a cap
  EXPECT_NEAR(extent().first, 0.0, 1e-3);
}

// Patent (64): the turns run at the corner speed with the pump slowed by the corner melt reduction.
TEST(Fill, CornerSpeedAndMeltReduction) {
  SectionParams s = plate();
  s.fill.corner_speed_mm_s = 10;
  s.fill.corner_melt_reduction = 0.3;
  const Toolpath tp = plan_toolpath(make_box({400, 300, 10}), {s}, {});
  const double area = bead_area_mm2(20, 10);
  int corners = 0;
  for (const Move* m : moves(tp, Feature::kFill)) {
    const bool corner = m->feed_mm_s == 10;
    corners += corner;
    EXPECT_NEAR(m->volume_mm3, area * m->length_mm() * (corner ? 0.7 : 1.0), 1e-6);
    if (corner) {
      EXPECT_LT(m->length_mm(), 1.5 * 20);  // turns are short
    }
  }
  EXPECT_GT(corners, 5);
}

// Patent (63): linking passes with rapids makes every pass its own bead; lead-in and lead-out have their
// lengths.
TEST(Fill, RapidsLeadInAndLeadOut) {
  const TriangleMesh box = make_box({400, 300, 10});
  SectionParams s = plate();
  const int linked = melt_ons(plan_toolpath(box, {s}, {}));
  s.fill.link_with_rapids = true;
  const Toolpath rapids = plan_toolpath(box, {s}, {});
  const int lines = static_cast<int>(moves(rapids, Feature::kFill).size());
  EXPECT_EQ(melt_ons(rapids), lines + 1);  // one per fill pass, plus the boundary pass
  EXPECT_GT(melt_ons(rapids), linked + 5);
  s.fill.lead_in_mm = 15;
  s.fill.lead_out_mm = 12;
  const Toolpath leads = plan_toolpath(box, {s}, {});
  const auto in = moves(leads, Feature::kLeadIn), out = moves(leads, Feature::kLeadOut);
  ASSERT_EQ(static_cast<int>(in.size()), lines);
  ASSERT_EQ(static_cast<int>(out.size()), lines);
  for (const Move* m : in) EXPECT_NEAR(m->length_mm(), 15, 1e-6);
  for (const Move* m : out) EXPECT_NEAR(m->length_mm(), 12, 1e-6);
}

// Patent (61), (65): a sparse fill that leaves its gaps lays top and bottom surface layers solid.
TEST(Fill, SparseFillKeepsSurfacesSolid) {
  SectionParams s = plate(30, 10);
  s.fill.style = FillStyleKind::kSparseZigzag;
  s.fill.sparse_fill_gaps = false;
  s.fill.max_sparse_spacing_mm = 3 * 18;  // every third line
  const Toolpath tp = plan_toolpath(make_box({400, 300, 30}), {s}, {});
  ASSERT_EQ(tp.layers.size(), 3u);
  std::vector<double> fill(3, 0.0);
  for (const Move* m : moves(tp, Feature::kFill)) fill[static_cast<std::size_t>(m->layer)] += m->length_mm();
  EXPECT_NEAR(fill[1] / fill[0], 1.0 / 3.0, 0.08);  // the middle layer is sparse
  EXPECT_NEAR(fill[2], fill[0], 1e-6 * fill[0]);    // bottom and top surfaces are solid
  // With the gap passes the sparse fill covers like a solid one.
  s.fill.sparse_fill_gaps = true;
  const Toolpath gaps = plan_toolpath(make_box({400, 300, 30}), {s}, {});
  double middle = 0;
  for (const Move* m : moves(gaps, Feature::kFill)) middle += m->layer == 1 ? m->length_mm() : 0.0;
  EXPECT_NEAR(middle / fill[0], 1.0, 0.1);
}

// Patent (62): variable bead regions lays beads down the voids the fill leaves against the boundary.
TEST(Fill, VariableBeadRegionsFillTheVoidsAgainstTheBoundary) {
  // A trapezoid: horizontal passes leave wedge-shaped voids along its slanted sides.
  SectionParams s = plate();
  s.containment_outside = {{{0, 0}, {400, 0}, {300, 300}, {100, 300}}};
  s.fill.angle_deg = 90;
  PlanStats smart, vbr;
  (void)plan_toolpath(make_box({400, 300, 10}), {s}, {}, &smart);
  s.fill.style = FillStyleKind::kVariableBeadRegions;
  (void)plan_toolpath(make_box({400, 300, 10}), {s}, {}, &vbr);
  EXPECT_EQ(smart.void_beads, 0);
  EXPECT_GT(vbr.voids_found, 0);
  EXPECT_GT(vbr.void_beads, 0);
}

// Patent (51)-(53) through the planner: prime and coast on every bead with the machine's extruder.
TEST(Fill, MeltEventsNeedAndUseTheExtruder) {
  const TriangleMesh box = make_box({400, 300, 10});
  SectionParams s = plate();
  s.melt.prime = true;
  s.melt.prime_time_s = 2;
  s.melt.prime_rpm = 30;
  s.melt.coast = true;
  s.melt.coast_distance_mm = 25;
  EXPECT_THROW((void)plan_toolpath(box, {s}, {}), InputError);
  Extruder pump;
  pump.displacement_mm3_per_rev = 10000;  // 10 cm3/rev
  const Toolpath tp = plan_toolpath(box, {s}, {}, nullptr, &pump);
  const int beads = melt_ons(tp);
  int primes = 0;
  double coast = 0;
  for (const Move& m : tp.moves) {
    if (m.kind == MoveKind::kDwell && m.feature == Feature::kPrime) {
      ++primes;
      EXPECT_NEAR(m.duration_s, 2, 1e-9);
      EXPECT_NEAR(m.volume_mm3, 30.0 / 60.0 * 10000 * 2, 1e-6);  // flow at 30 rpm for 2 s
    }
    if (m.kind == MoveKind::kPrint && m.feature == Feature::kCoast) coast += m.length_mm();
  }
  EXPECT_EQ(primes, beads);
  EXPECT_NEAR(coast, 25.0 * beads, 1e-6);
}

}  // namespace
}  // namespace beadtwin::slicer

namespace beadtwin::slicer {
namespace {

// Seed 002, eqs. 4-12: a bead growing linearly taller along the path, laid with a constant flow: the head
// slows as A(h) = π h²/4 + b_p h grows, the core width b_p stays w − h0, and each layer's top is a wedge.
TEST(Fill, VariableLayerHeightKeepsTheFlowConstant) {
  SectionParams s;
  s.name = "wedge";
  s.z_max_mm = 10;  // two layers of h0 = 5
  s.layer_height_mm = 5;
  s.bead_width_mm = 20;
  s.print_speed_mm_s = 40;
  s.travel_speed_mm_s = 200;
  s.outline_path = {{0, 0}, {200, 0}};
  s.outline_closed = false;
  s.height_slope = 0.01;  // 5 mm at x = 0, 7 mm at x = 200
  const Toolpath tp = plan_toolpath(TriangleMesh{}, {s}, {});
  const double b_p = 15, q = (kPi / 4 * 25 + b_p * 5) * 40;
  int pieces = 0;
  double last_feed = 1e9;
  for (const Move& m : tp.moves) {
    if (m.kind != MoveKind::kPrint) continue;
    ++pieces;
    const double x = 0.5 * (m.start.x() + m.end.x());
    const double h = 5 + 0.01 * x;
    EXPECT_NEAR(m.layer_height_mm, h, 1e-9);
    EXPECT_NEAR(m.bead_width_mm, b_p + h, 1e-9);
    // Eq. 12 written out: v = Q / (h (π h / 4 + b_p)).
    EXPECT_NEAR(m.feed_mm_s, q / (h * (kPi * h / 4 + b_p)), 1e-9);
    EXPECT_NEAR(m.volume_mm3 / (m.end - m.start).head<2>().norm() * m.feed_mm_s, q, 1e-6 * q);
    if (m.layer == 0) {
      EXPECT_LT(m.feed_mm_s, last_feed);  // slower as the bead grows
      last_feed = m.feed_mm_s;
    }
    // The top follows the wedge: layer n's top at (n + 1) h(x).
    EXPECT_NEAR(m.end.z(), (m.layer + 1) * (5 + 0.01 * m.end.x()), 1e-9);
  }
  EXPECT_GT(pieces, 2 * 30);  // cut finely: h changes by at most 1 % per piece
}

}  // namespace
}  // namespace beadtwin::slicer
