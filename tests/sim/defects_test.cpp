// The deposit's defects (sim/defects.hpp): runs merged, corners the roller cannot follow, travel moves that
// run into the part, and their descriptions; on hand-made toolpaths and grids.
#include "sim/defects.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/toolpath.hpp"
#include "core/units.hpp"
#include "sim/deposit.hpp"
#include "sim/travel_collision.hpp"
#include "tests/sim/lsam_beads.hpp"
#include "tests/sim/voxel_block.hpp"

namespace beadtwin {
namespace {

using testing::bead;
using testing::timed;
using testing::travel;
constexpr double kH = testing::kBeadHeight;

std::size_t count(const sim::Deposit& d, sim::DefectKind kind) {
  return static_cast<std::size_t>(std::count_if(d.defects.begin(), d.defects.end(),
                                                [&](const sim::Defect& x) { return x.kind == kind; }));
}

// A square with the roller down through its corners: a 90° turn at a point is tighter than any roller
// follows. The same square with corners rounded to 40 mm (in 10° steps) is fine for a 50 mm roller, whose
// inner edge stands still on a 25 mm radius.
TEST(Defects, RollerCornersTighterThanItFollows) {
  const auto square = [](double radius) {
    std::vector<Move> moves;
    std::vector<Eigen::Vector3d> points;
    const double half = 200.0;
    const Eigen::Vector2d centres[4] = {{half - radius, -half + radius},
                                        {half - radius, half - radius},
                                        {-half + radius, half - radius},
                                        {-half + radius, -half + radius}};
    for (int c = 0; c < 4; ++c)
      for (int k = 0; k <= 9; ++k) {
        const double a = (c * 90.0 - 90.0 + k * 10.0) * kPi / 180.0;
        points.emplace_back(centres[c].x() + radius * std::cos(a), centres[c].y() + radius * std::sin(a), kH);
      }
    points.push_back(points.front());
    for (std::size_t i = 0; i + 1 < points.size(); ++i)
      if ((points[i + 1] - points[i]).norm() > 1e-9) moves.push_back(bead(points[i], points[i + 1], 0));
    return timed(moves);
  };
  sim::DepositOptions o;
  o.flattening = sim::Flattening::kRoller;
  o.roller_width_mm = 50.0;
  o.voxel_size_mm = 2.54;
  const sim::Deposit sharp = sim::deposit(square(0.0), o);
  EXPECT_EQ(count(sharp, sim::DefectKind::kRollerCorner), 3u);  // the fourth corner is the loop's seam
  for (const sim::Defect& x : sharp.defects) {
    if (x.kind == sim::DefectKind::kRollerCorner) {
      EXPECT_NEAR(x.size, 90.0, 1e-6);
    }
  }
  EXPECT_EQ(count(sim::deposit(square(40.0), o), sim::DefectKind::kRollerCorner), 0u);
  // Lifted through the corner (the planner's corner pull-back), no defect.
  Toolpath lifted = square(0.0);
  for (Move& m : lifted.moves) m.roller_down = false;
  EXPECT_EQ(count(sim::deposit(lifted, o), sim::DefectKind::kRollerCorner), 0u);
}

// A travel move at the first layer's height back through the second layer's bead hits it.
TEST(Defects, TravelThroughThePartIsACollision) {
  std::vector<Move> moves = {bead({0, 0, kH}, {100, 0, kH}, 0), travel({100, 0, kH}, {100, 0, 2 * kH}, 1),
                             bead({100, 0, 2 * kH}, {0, 0, 2 * kH}, 1),
                             travel({0, 0, 2 * kH}, {50, -50, kH}, 1),
                             travel({50, -50, kH}, {50, 50, kH}, 1)};
  const sim::Deposit d = sim::deposit(timed(moves));
  ASSERT_EQ(count(d, sim::DefectKind::kCollision), 1u);
  const auto it = std::find_if(d.defects.begin(), d.defects.end(),
                               [](const sim::Defect& x) { return x.kind == sim::DefectKind::kCollision; });
  EXPECT_EQ(it->move, 4u);
  EXPECT_GT(it->size, 0.5 * kH);
  EXPECT_NE(it->detail.find("travel"), std::string::npos);
}

// Consecutive pieces of one layer with the same problem are one defect: volumes and lengths add up, depths
// keep the deepest. A gap between pieces, another layer or another kind starts a new one.
TEST(Defects, RunsOfConsecutivePiecesAreOneDefect) {
  Move layer0;
  layer0.layer = 0;
  layer0.source_line = 12;
  Move layer1 = layer0;
  layer1.layer = 1;
  const Eigen::Vector3d at(1, 2, 3);
  sim::DefectLog log;
  log.note(sim::DefectKind::kPlough, 4, 7, layer0, at, 1.0, true);
  log.note(sim::DefectKind::kPlough, 5, 8, layer0, at + Eigen::Vector3d::UnitX(), 2.0, true);
  log.note(sim::DefectKind::kCollision, 5, 8, layer0, at, 3.0, false);
  log.note(sim::DefectKind::kCollision, 6, 8, layer0, at, 2.0, false);
  log.note(sim::DefectKind::kPlough, 7, 9, layer0, at, 4.0, true);   // not after 5: a new one
  log.note(sim::DefectKind::kPlough, 8, 10, layer1, at, 8.0, true);  // another layer: a new one
  const std::vector<sim::Defect> d = log.take();
  ASSERT_EQ(d.size(), 4u);
  EXPECT_EQ(d[0].kind, sim::DefectKind::kPlough);
  EXPECT_EQ(d[0].size, 3.0);
  EXPECT_EQ(d[0].move, 7u);  // where the run starts
  EXPECT_EQ(d[0].position_mm, at);
  EXPECT_EQ(d[0].source_line, 12);
  EXPECT_EQ(d[1].kind, sim::DefectKind::kCollision);
  EXPECT_EQ(d[1].size, 3.0);
  EXPECT_EQ(d[2].size, 4.0);
  EXPECT_EQ(d[3].size, 8.0);
  EXPECT_EQ(d[3].layer, 1);
}

// Two right-angle turns 10 mm apart are within half a 50 mm roller's width of each other: one defect, the
// two turns together. Apart by more than a window, two. Joined moves only: a travel between ends the chain.
TEST(Defects, RollerCornersWithinAWindowAreOne) {
  const auto corners = [](double gap_mm, bool travel_between) {
    std::vector<Move> moves = {bead({0, 0, kH}, {100, 0, kH}), bead({100, 0, kH}, {100, gap_mm, kH})};
    if (travel_between) moves.push_back(travel({100, gap_mm, kH}, {100, gap_mm, kH + 5}));
    moves.push_back(bead({100, gap_mm, kH}, {0, gap_mm, kH}));
    sim::DefectLog log;
    sim::roller_corners(timed(moves), 50.0, log);
    return log.take();
  };
  const std::vector<sim::Defect> near = corners(10.0, false);
  ASSERT_EQ(near.size(), 1u);
  EXPECT_EQ(near[0].kind, sim::DefectKind::kRollerCorner);
  EXPECT_EQ(near[0].move, 1u);
  EXPECT_NEAR(near[0].size, 180.0, 1e-9);
  const std::vector<sim::Defect> apart = corners(60.0, false);
  ASSERT_EQ(apart.size(), 2u);
  EXPECT_NEAR(apart[0].size, 90.0, 1e-9);
  EXPECT_EQ(apart[1].move, 2u);
  const std::vector<sim::Defect> broken = corners(10.0, true);
  ASSERT_EQ(broken.size(), 1u);  // the first corner only: the travel ends the chain
  EXPECT_NEAR(broken[0].size, 90.0, 1e-9);
}

// A block of full 1 mm voxels, x 0..20, y 0..10, z 0..6 mm. A travel through it at 4.2 mm runs 1.8 mm
// into it; one above it, or beside it, runs into nothing; one passing 1 mm beside it does with a nozzle 3 mm
// across.
TEST(Defects, TravelCollisionIsTheDepthAboveTheTip) {
  const openvdb::FloatGrid::Ptr fill = testing::full_block({20, 10, 6});
  const auto depth = [&](const Eigen::Vector3d& from, const Eigen::Vector3d& to, double nozzle_mm) {
    return sim::travel_collision_mm(travel(from, to), *fill, 1.0, nozzle_mm);
  };
  EXPECT_NEAR(depth({-5, 5, 4.2}, {25, 5, 4.2}, 0.0), 1.8, 1e-9);
  EXPECT_EQ(depth({-5, 5, 6.5}, {25, 5, 6.5}, 0.0), 0.0);
  EXPECT_EQ(depth({-5, -1, 4.2}, {25, -1, 4.2}, 0.0), 0.0);
  EXPECT_NEAR(depth({-5, -1, 4.2}, {25, -1, 4.2}, 3.0), 1.8, 1e-9);
  // Material more than four voxels above the tip is out of its reach.
  EXPECT_EQ(depth({-5, 5, -4.5}, {25, 5, -4.5}, 0.0), 0.0);
}

TEST(Defects, DescriptionsSayWhatAndHowMuch) {
  sim::Defect d;
  d.kind = sim::DefectKind::kCollision;
  d.size = 2.5;
  d.detail = "travel";
  EXPECT_EQ(sim::describe(d), "a travel move runs 2.5 mm into the part");
  d.detail.clear();
  EXPECT_NE(sim::describe(d).find("2.5 mm above the bead's top"), std::string::npos);
  d.kind = sim::DefectKind::kVoid;
  d.size = 120.0;
  d.detail = "between passes";
  EXPECT_EQ(sim::describe(d), "void of 120 mm³ between passes");
  d.kind = sim::DefectKind::kRollerCorner;
  d.size = 90.0;
  EXPECT_NE(sim::describe(d).find("a turn of 90°"), std::string::npos);
  EXPECT_EQ(sim::to_string(sim::DefectKind::kRollerCorner), "roller_corner");
  EXPECT_EQ(sim::to_string(sim::DefectKind::kUnsupported), "unsupported");
}

}  // namespace
}  // namespace beadtwin
