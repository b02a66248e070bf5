#include "sim/deposit.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <vector>

#include <tbb/global_control.h>

#include "core/bead.hpp"
#include "core/error.hpp"
#include "core/units.hpp"
#include "sim/bead_section.hpp"
#include "tests/sim/lsam_beads.hpp"

namespace beadtwin {
namespace {

using testing::bead;
using testing::kBeadHeight;
using testing::kBeadWidth;
using testing::timed;
using testing::travel;

// Moves as given, without timing (start_s = duration_s = 0).
Toolpath untimed(std::vector<Move> moves) {
  Toolpath toolpath;
  toolpath.moves = std::move(moves);
  return toolpath;
}

// `count` beads along x, `pitch` apart in y, all laid in the same direction with travels between them.
Toolpath parallel_beads(int count, double pitch, double length, int layers = 1) {
  std::vector<Move> moves;
  Eigen::Vector3d at(0.0, 0.0, kBeadHeight);
  for (int l = 0; l < layers; ++l) {
    const double z = (l + 1) * kBeadHeight;
    for (int n = 0; n < count; ++n) {
      const Eigen::Vector3d a(0.0, n * pitch, z), b(length, n * pitch, z);
      moves.push_back(travel(at, a));
      moves.push_back(bead(a, b, l));
      at = b;
    }
  }
  return timed(std::move(moves));
}

float fill_at(const sim::Deposit& d, const Eigen::Vector3d& p) {
  return d.fill->tree().getValue(sim::voxel_containing(p, d.voxel_size_mm));
}

double relative_error(double value, double reference) {
  return std::abs(value - reference) / reference;
}

void expect_fill_within_unit_range(const sim::Deposit& d) {
  for (auto it = d.fill->cbeginValueOn(); it; ++it) {
    ASSERT_GT(*it, 0.0f);
    ASSERT_LE(*it, 1.0f);
  }
}

// ---- bead cross-section -------------------------------------------------------------------------------

TEST(StadiumSection, WidthIsTheInverseOfArea) {
  for (const double h : {1.0, 2.5, kBeadHeight})
    for (const double w : {h, 1.5 * h, 10.0, kBeadWidth, 40.0}) {
      if (w < h) continue;
      EXPECT_NEAR(bead_width_mm(bead_area_mm2(w, h), h), w, 1e-12 * w) << w << " x " << h;
    }
  // A round bead (w = h) is a disc.
  EXPECT_NEAR(bead_area_mm2(3.0, 3.0), kPi * 9.0 / 4.0, 1e-12);
}

TEST(StadiumSection, PatentRoundBeadFlattenedToAFifthOfAnInch) {
  // Patent check (docs/physics.md, bead cross-section): a 0.5 in round bead, A = π·0.25² = 0.196 in²,
  // flattened to 0.20 in is about 1.02 in wide; and 0.83 in × 0.20 in means A ≈ 0.157 in².
  const double area_mm2 = kPi * std::pow(0.25 * kMmPerInch, 2);
  EXPECT_NEAR(area_mm2 / (kMmPerInch * kMmPerInch), 0.196, 0.001);
  const double width_mm = bead_width_mm(area_mm2, kBeadHeight);
  EXPECT_NEAR(width_mm / kMmPerInch, 1.02, 0.01);
  EXPECT_NEAR(bead_area_mm2(kBeadWidth, kBeadHeight) / (kMmPerInch * kMmPerInch), 0.157, 0.001);
}

TEST(StadiumSection, AreaTooSmallToReachTheRollerIsNotAStadium) {
  EXPECT_THROW(bead_width_mm(0.5 * kPi * kBeadHeight * kBeadHeight / 4.0, kBeadHeight), InternalError);
  // The deposit lays it as a round bead of the same area, thinner than the layer.
  const sim::BeadProfile round = sim::moving_bead_profile(10.0, kBeadHeight);
  EXPECT_DOUBLE_EQ(round.core_half_width_mm, 0.0);
  EXPECT_NEAR(round.area_mm2(), 10.0, 1e-12);
  EXPECT_LT(round.height_mm(), kBeadHeight);
}

TEST(StadiumSection, PuddleHoldsItsVolume) {
  for (const double v : {1.0, 50.0, 68.0, 69.0, 500.0, 20000.0}) {
    const sim::BeadProfile p = sim::puddle_profile(v, kBeadHeight);
    EXPECT_NEAR(p.revolved_volume_mm3(), v, 1e-9 * v) << v;
    EXPECT_LE(p.height_mm(), kBeadHeight * (1 + 1e-12));
  }
}

// ---- conventions --------------------------------------------------------------------------------------

TEST(DepositConventions, VoxelIJKSpansIToIPlusOneAndTheTransformAgrees) {
  const double s = 2.0;
  const auto transform = sim::deposit_transform(s);
  const openvdb::Vec3d centre = transform->indexToWorld(openvdb::Coord(0, 0, 0));
  EXPECT_DOUBLE_EQ(centre.x(), 1.0);
  EXPECT_DOUBLE_EQ(centre.z(), 1.0);
  const Eigen::Vector3d p(0.1, 3.9, -0.1);
  const openvdb::Coord ijk = sim::voxel_containing(p, s);
  EXPECT_EQ(ijk, openvdb::Coord(0, 1, -1));
  EXPECT_EQ(transform->worldToIndexCellCentered(openvdb::Vec3d(p.x(), p.y(), p.z())), ijk);
  EXPECT_TRUE(sim::voxel_center_mm(ijk, s).isApprox(Eigen::Vector3d(1.0, 3.0, -1.0)));
}

TEST(Deposit, EmptyToolpathGivesEmptyGrids) {
  const sim::Deposit d = sim::deposit(timed({travel({0, 0, 5}, {100, 0, 5})}));
  ASSERT_TRUE(d.fill && d.time && d.layer);
  EXPECT_EQ(d.active_voxels, 0u);
  EXPECT_EQ(d.deposited_volume_mm3, 0.0);
  EXPECT_EQ(d.porosity, 0.0);
}

// ---- one bead -----------------------------------------------------------------------------------------

TEST(Deposit, SingleStraightBeadHoldsItsVolumeAndWidth) {
  // Off the voxel grid on purpose.
  const Eigen::Vector3d a(10.3, 20.7, kBeadHeight), b(510.3, 20.7, kBeadHeight);
  const Toolpath toolpath = timed({bead(a, b)});
  const Move& m = toolpath.moves[0];
  const sim::Deposit d = sim::deposit(toolpath);

  EXPECT_DOUBLE_EQ(d.voxel_size_mm, kBeadHeight / 2.0);
  EXPECT_NEAR(d.commanded_volume_mm3, m.volume_mm3, 1e-9 * m.volume_mm3);
  EXPECT_LT(relative_error(d.deposited_volume_mm3, d.commanded_volume_mm3), 1e-6);
  EXPECT_LT(relative_error(d.swept_volume_mm3, d.commanded_volume_mm3), 0.02);
  EXPECT_LT(d.redistributed_volume_mm3, 1e-3 * d.commanded_volume_mm3);
  expect_fill_within_unit_range(d);

  // Width and section measured on the voxels across the middle of the bead.
  const double s = d.voxel_size_mm;
  const openvdb::Coord mid = sim::voxel_containing(0.5 * (a + b), s);
  const auto acc = d.fill->getConstAccessor();
  double widest_mm = 0.0, section_mm2 = 0.0;
  for (int k = mid.z() - 6; k <= mid.z() + 6; ++k) {
    double row = 0.0;
    for (int j = mid.y() - 20; j <= mid.y() + 20; ++j) row += acc.getValue(openvdb::Coord(mid.x(), j, k));
    widest_mm = std::max(widest_mm, row * s);
    section_mm2 += row * s * s;
  }
  const double area = bead_area_mm2(kBeadWidth, kBeadHeight);
  std::printf(
      "single bead: voxel %.3f mm, measured width %.3f mm (formula %.3f, mean %.3f), section %.2f mm² (A "
      "%.2f)\n",
      s, widest_mm, kBeadWidth, area / kBeadHeight, section_mm2, area);
  EXPECT_NEAR(widest_mm, kBeadWidth, s);
  EXPECT_LT(relative_error(section_mm2, area), 0.02);

  // Bead sits between z - h and z.
  EXPECT_EQ(fill_at(d, {260.0, 20.7, kBeadHeight + 0.5 * s}), 0.0f);
  EXPECT_EQ(fill_at(d, {260.0, 20.7, -0.5 * s}), 0.0f);
  // Full inside; not exactly 1 because the sampled sweep is a little off A·L and the move's material is
  // scaled to fit it.
  EXPECT_NEAR(fill_at(d, {260.0, 20.7, 0.5 * s}), 1.0f, 0.02f);

  // Time runs along the bead; the layer is the move's.
  const openvdb::Coord c = sim::voxel_containing({260.3, 20.7, 0.5 * s}, s);
  const double expected_t =
      m.start_s + (sim::voxel_center_mm(c, s).x() - a.x()) / (b.x() - a.x()) * m.duration_s;
  EXPECT_NEAR(d.time->tree().getValue(c), expected_t, 0.01 * m.duration_s);
  EXPECT_EQ(d.layer->tree().getValue(c), 0);
  EXPECT_EQ(d.layer->tree().getValue(openvdb::Coord(0, 0, 100)), -1);
  EXPECT_EQ(d.active_voxels, static_cast<std::size_t>(d.time->activeVoxelCount()));
}

TEST(Deposit, FineVoxelsResolveTheStadium) {
  const Eigen::Vector3d a(0.0, 0.0, kBeadHeight), b(100.0, 0.0, kBeadHeight);
  sim::DepositOptions options;
  options.voxel_size_mm = 0.5;
  const sim::Deposit d = sim::deposit(timed({bead(a, b)}), options);
  // At the bead's mid-height (z ≈ 2.5 mm) the whole width (to y = 10.54 mm) is there, and nothing beyond it.
  EXPECT_GT(fill_at(d, {50.0, 10.25, 2.75}), 0.98f);
  EXPECT_EQ(fill_at(d, {50.0, 11.25, 2.75}), 0.0f);
  // Near the top the rounded sides have pulled in: at z = 4.5 mm the bead reaches y = 9.61 mm, at 5 mm
  // 8.63 mm.
  EXPECT_EQ(fill_at(d, {50.0, 10.25, 4.75}), 0.0f);
  EXPECT_GT(fill_at(d, {50.0, 8.25, 4.75}), 0.98f);
  EXPECT_LT(relative_error(d.swept_volume_mm3, d.commanded_volume_mm3), 0.005);
}

TEST(Deposit, DiagonalBeadKeepsItsSection) {
  const Eigen::Vector3d a(3.1, -7.0, kBeadHeight);
  const Eigen::Vector3d dir(std::cos(0.5), std::sin(0.5), 0.0);
  const Eigen::Vector3d across(-dir.y(), dir.x(), 0.0);
  const sim::Deposit d = sim::deposit(timed({bead(a, a + 800.0 * dir)}));
  EXPECT_LT(relative_error(d.swept_volume_mm3, d.commanded_volume_mm3), 0.01);
  EXPECT_LT(relative_error(d.deposited_volume_mm3, d.commanded_volume_mm3), 1e-6);
  const Eigen::Vector3d mid = a + 400.0 * dir - Eigen::Vector3d(0, 0, 0.75 * kBeadHeight);
  const double reach = 0.5 * kBeadWidth;
  EXPECT_GT(fill_at(d, mid + (reach - 2.0 * d.voxel_size_mm) * across), 0.98f);
  EXPECT_GT(fill_at(d, mid - (reach - 2.0 * d.voxel_size_mm) * across), 0.98f);
  EXPECT_EQ(fill_at(d, mid + (reach + 1.5 * d.voxel_size_mm) * across), 0.0f);
  EXPECT_EQ(fill_at(d, mid - (reach + 1.5 * d.voxel_size_mm) * across), 0.0f);
}

TEST(Deposit, RoundFreeEndsSweepMoreButHoldTheSameVolume) {
  const Toolpath toolpath = timed({bead({0, 0, kBeadHeight}, {200, 0, kBeadHeight})});
  sim::DepositOptions options;
  options.round_free_ends = true;
  const sim::Deposit round = sim::deposit(toolpath, options);
  const sim::Deposit square = sim::deposit(toolpath);
  EXPECT_GT(round.swept_volume_mm3, 1.02 * square.swept_volume_mm3);
  EXPECT_LT(relative_error(round.deposited_volume_mm3, round.commanded_volume_mm3), 1e-6);
  EXPECT_GT(fill_at(round, {-0.3 * kBeadWidth, 0, 0.5 * round.voxel_size_mm}), 0.0f);
  EXPECT_EQ(fill_at(square, {-0.3 * kBeadWidth, 0, 0.5 * round.voxel_size_mm}), 0.0f);
}

TEST(Deposit, CornerIsRoundOutsideAndConservesVolume) {
  const double h = kBeadHeight;
  const Toolpath toolpath = timed({bead({0, 0, h}, {300, 0, h}), bead({300, 0, h}, {300, 300, h})});
  const sim::Deposit d = sim::deposit(toolpath);
  EXPECT_LT(relative_error(d.deposited_volume_mm3, d.commanded_volume_mm3), 1e-6);
  // The joined corner is the swept footprint: no material counted twice, little to push around.
  EXPECT_LT(relative_error(d.swept_volume_mm3, d.commanded_volume_mm3), 0.01);
  EXPECT_LT(d.redistributed_volume_mm3, 0.01 * d.commanded_volume_mm3);
  const double z = 0.5 * d.voxel_size_mm;
  const double w = kBeadWidth;
  EXPECT_EQ(fill_at(d, {300 + 0.45 * w, -0.45 * w, z}), 0.0f);  // a mitre would fill this
  EXPECT_GT(fill_at(d, {300 + 0.25 * w, -0.25 * w, z}), 0.5f);
  EXPECT_EQ(fill_at(d, {300 - 0.25 * w, 0.25 * w, z}), 1.0f);  // inside of the corner
}

TEST(Deposit, ClosedLoopJoinsItsSeam) {
  const double h = kBeadHeight;
  const Toolpath toolpath = timed({bead({0, 0, h}, {200, 0, h}), bead({200, 0, h}, {200, 200, h}),
                                   bead({200, 200, h}, {0, 200, h}), bead({0, 200, h}, {0, 0, h})});
  const sim::Deposit d = sim::deposit(toolpath);
  EXPECT_LT(relative_error(d.deposited_volume_mm3, d.commanded_volume_mm3), 1e-6);
  // Each 90° corner sweeps (w/2)²(1 − π/4) less plan area than A·L counts.
  EXPECT_LT(relative_error(d.swept_volume_mm3, d.commanded_volume_mm3), 0.02);
  EXPECT_LT(d.swept_volume_mm3, d.commanded_volume_mm3);
  // The start corner is as round as the others.
  EXPECT_EQ(fill_at(d, {-0.45 * kBeadWidth, -0.45 * kBeadWidth, 0.5 * d.voxel_size_mm}), 0.0f);
  EXPECT_GT(fill_at(d, {-0.25 * kBeadWidth, -0.25 * kBeadWidth, 0.5 * d.voxel_size_mm}), 0.5f);
}

TEST(Deposit, PuddleFromADwell) {
  Move dwell;
  dwell.kind = MoveKind::kDwell;
  dwell.event = ExtruderEvent::kPrime;
  dwell.start = dwell.end = Eigen::Vector3d(50, 50, kBeadHeight);
  dwell.volume_mm3 = 3000.0;
  dwell.layer_height_mm = kBeadHeight;
  dwell.duration_s = 2.0;
  const sim::Deposit d = sim::deposit(timed({dwell}));
  EXPECT_LT(relative_error(d.deposited_volume_mm3, 3000.0), 1e-6);
  EXPECT_LT(relative_error(d.swept_volume_mm3, 3000.0), 0.03);
  EXPECT_GT(fill_at(d, {50, 50, 0.5 * d.voxel_size_mm}), 0.99f);
  EXPECT_EQ(fill_at(d, {50, 50, kBeadHeight + 0.5 * d.voxel_size_mm}), 0.0f);
  // Complete when the dwell ends.
  EXPECT_FLOAT_EQ(d.time->tree().getValue(sim::voxel_containing({50, 50, 1}, d.voxel_size_mm)), 2.0f);
}

TEST(Deposit, StarvedBeadIsRoundUnderTheRoller) {
  Move m = bead({0, 0, kBeadHeight}, {200, 0, kBeadHeight});
  const double area = 0.3 * kPi * kBeadHeight * kBeadHeight / 4.0;
  m.volume_mm3 = area * m.length_mm();
  sim::DepositOptions options;
  options.voxel_size_mm = 0.5;
  const sim::Deposit d = sim::deposit(timed({m}), options);
  EXPECT_LT(relative_error(d.deposited_volume_mm3, d.commanded_volume_mm3), 1e-6);
  const double diameter = 2.0 * std::sqrt(area / kPi);
  EXPECT_GT(fill_at(d, {100, 0.25, kBeadHeight - 0.5 * diameter}), 0.5f);
  EXPECT_EQ(fill_at(d, {100, 0.25, kBeadHeight - diameter - 0.6}), 0.0f);  // hangs from the roller
  EXPECT_EQ(fill_at(d, {100, 0.25, kBeadHeight + 0.75}), 0.0f);
}

// ---- conservation -------------------------------------------------------------------------------------

TEST(Deposit, OverlappingPassesConserveVolumeByPushingMaterialAside) {
  const double h = kBeadHeight;
  // Second pass a third of a bead width over the first.
  const Toolpath toolpath =
      timed({bead({0, 0, h}, {300, 0, h}), travel({300, 0, h}, {0, 7, h}), bead({0, 7, h}, {300, 7, h})});
  const sim::Deposit d = sim::deposit(toolpath);
  std::printf("overlap: commanded %.1f mm³, deposited %.1f mm³, redistributed %.1f mm³\n",
              d.commanded_volume_mm3, d.deposited_volume_mm3, d.redistributed_volume_mm3);
  EXPECT_LT(relative_error(d.deposited_volume_mm3, d.commanded_volume_mm3), 1e-6);
  EXPECT_GT(d.redistributed_volume_mm3, 0.1 * d.commanded_volume_mm3);
  expect_fill_within_unit_range(d);
}

TEST(Deposit, SamePathTwiceSqueezesTheSecondBeadAsideAndUp) {
  const double h = kBeadHeight;
  const Toolpath toolpath =
      timed({bead({0, 0, h}, {300, 0, h}), travel({300, 0, h}, {0, 0, h}), bead({0, 0, h}, {300, 0, h})});
  const sim::Deposit d = sim::deposit(toolpath);
  EXPECT_LT(relative_error(d.deposited_volume_mm3, d.commanded_volume_mm3), 1e-6);
  EXPECT_GT(d.redistributed_volume_mm3, 0.45 * d.commanded_volume_mm3);
  expect_fill_within_unit_range(d);
  // The second bead squeezes a little wider beside the first, in the same layer, and the rest rises above
  // it (the roller ploughs); nothing runs off further than that.
  EXPECT_EQ(fill_at(d, {150, 0.5 * kBeadWidth + 0.5 * d.voxel_size_mm, 0.5 * d.voxel_size_mm}), 1.0f);
  EXPECT_GT(fill_at(d, {150, 0, h + 0.5 * d.voxel_size_mm}), 0.0f);
  EXPECT_EQ(fill_at(d, {150, 0.5 * kBeadWidth + 3.0 * d.voxel_size_mm, 0.5 * d.voxel_size_mm}), 0.0f);
}

TEST(Deposit, RepeatedPassesPileUpWhenTheSlabIsFull) {
  const double h = kBeadHeight;
  std::vector<Move> moves;
  for (int pass = 0; pass < 5; ++pass) {
    moves.push_back(travel({300, 0, h}, {0, 0, h}));
    moves.push_back(bead({0, 0, h}, {300, 0, h}));
  }
  const sim::Deposit d = sim::deposit(timed(moves));
  EXPECT_LT(relative_error(d.deposited_volume_mm3, d.commanded_volume_mm3), 1e-6);
  expect_fill_within_unit_range(d);
  EXPECT_GT(fill_at(d, {150, 0, h + 0.5 * d.voxel_size_mm}), 0.0f);
}

// A messy program: random segments, overlaps, a hairpin, tiny moves, puddles, ramps, several layers.
Toolpath messy_toolpath() {
  std::uint64_t state = 12345;
  const auto uniform = [&state](double lo, double hi) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return lo + (hi - lo) * static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  std::vector<Move> moves;
  Eigen::Vector3d at(0, 0, kBeadHeight);
  for (int layer = 0; layer < 3; ++layer) {
    const double z = (layer + 1) * kBeadHeight;
    at.z() = z;
    for (int n = 0; n < 60; ++n) {
      const Eigen::Vector3d to(uniform(0, 150), uniform(0, 150), z);
      const double width = uniform(kBeadHeight, 25.0);
      const double roll = uniform(0, 1);
      if (roll < 0.1) {
        moves.push_back(travel(at, to));
      } else if (roll < 0.15) {
        Move m = bead(at, at, layer, width);
        m.kind = MoveKind::kDwell;
        m.volume_mm3 = uniform(1, 800);
        moves.push_back(m);
        continue;
      } else if (roll < 0.2) {
        Move m = bead(at, at + Eigen::Vector3d(uniform(-0.01, 0.01), 0, 0), layer, width);
        m.volume_mm3 = uniform(0.1, 5);
        moves.push_back(m);
      } else if (roll < 0.25) {
        moves.push_back(bead(at, at + Eigen::Vector3d(40, 0, 0), layer, width));
        moves.push_back(bead(at + Eigen::Vector3d(40, 0, 0), at + Eigen::Vector3d(0, 1, 0), layer, width));
        at = moves.back().end;
        continue;
      } else {
        Move m = bead(at, to + Eigen::Vector3d(0, 0, uniform(0, 0.5)), layer, width);
        m.volume_mm3 *= uniform(0.2, 1.8);
        moves.push_back(m);
      }
      at = moves.back().end;
    }
  }
  return timed(std::move(moves));
}

TEST(Deposit, MessyToolpathConservesVolume) {
  const sim::Deposit d = sim::deposit(messy_toolpath());
  std::printf("messy: commanded %.1f, deposited %.1f, swept %.1f, redistributed %.1f mm³, porosity %.4f\n",
              d.commanded_volume_mm3, d.deposited_volume_mm3, d.swept_volume_mm3, d.redistributed_volume_mm3,
              d.porosity);
  EXPECT_LT(relative_error(d.deposited_volume_mm3, d.commanded_volume_mm3), 1e-6);
  EXPECT_GT(d.redistributed_volume_mm3, 0.0);
  expect_fill_within_unit_range(d);
  EXPECT_EQ(d.active_voxels, static_cast<std::size_t>(d.time->activeVoxelCount()));
  EXPECT_EQ(d.active_voxels, static_cast<std::size_t>(d.layer->activeVoxelCount()));
}

TEST(Deposit, ResultDoesNotDependOnThreads) {
  const Toolpath toolpath = messy_toolpath();
  const auto run = [&toolpath](std::size_t threads) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return sim::deposit(toolpath);
  };
  const sim::Deposit one = run(1);
  const sim::Deposit two = run(2);
  EXPECT_EQ(one.deposited_volume_mm3, two.deposited_volume_mm3);
  EXPECT_EQ(one.swept_volume_mm3, two.swept_volume_mm3);
  EXPECT_EQ(one.porosity, two.porosity);
  ASSERT_EQ(one.active_voxels, two.active_voxels);
  const auto fill2 = two.fill->getConstAccessor();
  const auto time2 = two.time->getConstAccessor();
  const auto layer1 = one.layer->getConstAccessor();
  const auto layer2 = two.layer->getConstAccessor();
  for (auto it = one.fill->cbeginValueOn(); it; ++it) {
    ASSERT_EQ(*it, fill2.getValue(it.getCoord()));
    ASSERT_EQ(one.time->tree().getValue(it.getCoord()), time2.getValue(it.getCoord()));
    ASSERT_EQ(layer1.getValue(it.getCoord()), layer2.getValue(it.getCoord()));
    ASSERT_EQ(one.move->tree().getValue(it.getCoord()), two.move->tree().getValue(it.getCoord()));
  }
  // What it found is the same too: the substrate under every bead, the ploughs, the voids.
  ASSERT_EQ(one.defects.size(), two.defects.size());
  for (std::size_t i = 0; i < one.defects.size(); ++i) {
    EXPECT_EQ(one.defects[i].kind, two.defects[i].kind);
    EXPECT_EQ(one.defects[i].move, two.defects[i].move);
    EXPECT_EQ(one.defects[i].size, two.defects[i].size);
  }
  ASSERT_EQ(one.layers.size(), two.layers.size());
  for (std::size_t i = 0; i < one.layers.size(); ++i) {
    EXPECT_EQ(one.layers[i].mean_bead_height_mm, two.layers[i].mean_bead_height_mm);
    EXPECT_EQ(one.layers[i].plough_volume_mm3, two.layers[i].plough_volume_mm3);
  }
  EXPECT_GT(one.plough_volume_mm3, 0.0);  // the messy beads overlap: there is something to compare
}

// ---- porosity -----------------------------------------------------------------------------------------

TEST(Deposit, PorosityIsSmallAtTheIdealPitchAndGrowsWithWiderPitch) {
  const double ideal = bead_area_mm2(kBeadWidth, kBeadHeight) / kBeadHeight;
  const sim::Deposit tight = sim::deposit(parallel_beads(8, ideal, 400.0));
  const sim::Deposit loose = sim::deposit(parallel_beads(8, 1.5 * ideal, 400.0));
  const sim::Deposit single = sim::deposit(parallel_beads(1, ideal, 400.0));
  std::printf(
      "porosity: single bead %.4f, ideal pitch %.2f mm %.4f, 1.5x pitch %.4f (redistributed %.2f %%)\n",
      single.porosity, ideal, tight.porosity, loose.porosity,
      100.0 * tight.redistributed_volume_mm3 / tight.commanded_volume_mm3);
  EXPECT_LT(single.porosity, 0.01);  // a bead's rounded flanks are outside, not void
  EXPECT_LT(tight.porosity, 0.03);
  EXPECT_GT(loose.porosity, 0.15);
  EXPECT_LT(relative_error(tight.deposited_volume_mm3, tight.commanded_volume_mm3), 1e-6);
  EXPECT_LT(relative_error(loose.deposited_volume_mm3, loose.commanded_volume_mm3), 1e-6);
}

TEST(Deposit, LaterLayersStackOnEarlierOnes) {
  const double ideal = bead_area_mm2(kBeadWidth, kBeadHeight) / kBeadHeight;
  const sim::Deposit d = sim::deposit(parallel_beads(4, ideal, 200.0, 3));
  EXPECT_LT(d.porosity, 0.03);
  const openvdb::Coord lower = sim::voxel_containing({100, ideal, 0.5 * kBeadHeight}, d.voxel_size_mm);
  const openvdb::Coord upper = sim::voxel_containing({100, ideal, 2.5 * kBeadHeight}, d.voxel_size_mm);
  EXPECT_EQ(d.layer->tree().getValue(lower), 0);
  EXPECT_EQ(d.layer->tree().getValue(upper), 2);
  EXPECT_LT(d.time->tree().getValue(lower), d.time->tree().getValue(upper));
}

// The part as it stood after layer 1 of 3: the first two layers' material, none of the third's.
TEST(Deposit, FillUpToALayerKeepsThatLayerAndTheOnesBelow) {
  const double ideal = bead_area_mm2(kBeadWidth, kBeadHeight) / kBeadHeight;
  const sim::Deposit d = sim::deposit(parallel_beads(4, ideal, 200.0, 3));
  const openvdb::FloatGrid::Ptr two = sim::fill_up_to_layer(d, 1);
  double kept = 0.0, expected = 0.0;
  auto layer_at = d.layer->getConstAccessor();
  for (auto it = d.fill->cbeginValueOn(); it; ++it) {
    const int layer = layer_at.getValue(it.getCoord());
    if (layer >= 0 && layer <= 1) expected += *it;
  }
  for (auto it = two->cbeginValueOn(); it; ++it) {
    kept += *it;
    EXPECT_LE(layer_at.getValue(it.getCoord()), 1);
  }
  EXPECT_DOUBLE_EQ(kept, expected);
  // About two thirds of the material, and the top of the second layer is the top.
  double all = 0.0;
  for (auto it = d.fill->cbeginValueOn(); it; ++it) all += *it;
  EXPECT_NEAR(kept / all, 2.0 / 3.0, 0.03);
  const openvdb::Coord top = sim::voxel_containing({100, ideal, 2.5 * kBeadHeight}, d.voxel_size_mm);
  EXPECT_FALSE(two->tree().isValueOn(top));
  EXPECT_TRUE(two->transform() == d.fill->transform());
  // By time: at the start of the third layer, the same material as after the second.
  const openvdb::FloatGrid::Ptr at = sim::fill_up_to_time(d, d.time->tree().getValue(top) - 1e-3);
  double at_kept = 0.0;
  for (auto it = at->cbeginValueOn(); it; ++it) at_kept += *it;
  EXPECT_GE(at_kept, kept - 1e-9);
  EXPECT_LT(at_kept, all);
  EXPECT_FALSE(at->tree().isValueOn(top));
}

// ---- bad input ----------------------------------------------------------------------------------------

TEST(Deposit, ZeroLayerHeightIsAnInputErrorNamingTheMove) {
  std::vector<Move> moves = {bead({0, 0, 5}, {100, 0, 5}), bead({100, 0, 5}, {100, 100, 5})};
  moves[1].layer_height_mm = 0.0;
  moves[1].source_line = 345;
  try {
    sim::deposit(timed(moves));
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, 345);
    EXPECT_EQ(e.key(), "move 1");
    EXPECT_NE(e.message().find("layer height"), std::string::npos) << e.what();
  }
}

TEST(Deposit, EveryBadMoveIsReported) {
  std::vector<Move> moves = {bead({0, 0, 5}, {100, 0, 5}), bead({100, 0, 5}, {100, 100, 5}),
                             bead({100, 100, 5}, {0, 100, 5})};
  moves[0].volume_mm3 = -1.0;
  moves[1].end.x() = std::nan("");
  moves[2].layer_height_mm = -5.0;
  try {
    sim::deposit(untimed(moves));
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("3 problems"), std::string::npos) << what;
    EXPECT_NE(what.find("move 0: volume"), std::string::npos) << what;
    EXPECT_NE(what.find("move 1: coordinates"), std::string::npos) << what;
    EXPECT_NE(what.find("move 2: layer height"), std::string::npos) << what;
  }
}

TEST(Deposit, BadOptionsAreInputErrors) {
  const Toolpath toolpath = timed({bead({0, 0, 5}, {100, 0, 5})});
  sim::DepositOptions options;
  options.voxel_size_mm = -1.0;
  EXPECT_THROW(sim::deposit(toolpath, options), InputError);
  options.voxel_size_mm = 1e-4;  // far too many voxels
  EXPECT_THROW(sim::deposit(toolpath, options), InputError);
  options.voxel_size_mm = 1e-8;  // beyond the voxel index range
  EXPECT_THROW(sim::deposit(toolpath, options), InputError);
  options.voxel_size_mm = 0.0;
  options.supersample = 0;
  EXPECT_THROW(sim::deposit(toolpath, options), InputError);
}

// ---- scale --------------------------------------------------------------------------------------------

TEST(Deposit, HundredMetresOfBeadTakeSeconds) {
  // A 1 m square filled by a zigzag raster at the ideal pitch, two layers: about 100 m of bead.
  const double ideal = bead_area_mm2(kBeadWidth, kBeadHeight) / kBeadHeight;
  std::vector<Move> moves;
  for (int layer = 0; layer < 2; ++layer) {
    const double z = (layer + 1) * kBeadHeight;
    const int lines = static_cast<int>(1000.0 / ideal);
    for (int n = 0; n < lines; ++n) {
      const double y = n * ideal;
      const bool forward = n % 2 == 0;
      const Eigen::Vector3d a(forward ? 0.0 : 1000.0, y, z), b(forward ? 1000.0 : 0.0, y, z);
      moves.push_back(bead(a, b, layer));
      if (n + 1 < lines) moves.push_back(bead(b, b + Eigen::Vector3d(0, ideal, 0), layer));
    }
  }
  const Toolpath toolpath = timed(std::move(moves));
  const auto t0 = std::chrono::steady_clock::now();
  const sim::Deposit d = sim::deposit(toolpath);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%.1f m of bead: %zu active voxels, porosity %.4f, redistributed %.3f %%, %.2f s\n",
              toolpath.print_length_mm() / 1000.0, d.active_voxels, d.porosity,
              100.0 * d.redistributed_volume_mm3 / d.commanded_volume_mm3, seconds);
  EXPECT_GT(toolpath.print_length_mm(), 95e3);
  EXPECT_LT(relative_error(d.deposited_volume_mm3, d.commanded_volume_mm3), 1e-6);
  EXPECT_LT(d.porosity, 0.03);
  EXPECT_LT(seconds, 60.0);
}

}  // namespace
}  // namespace beadtwin

namespace beadtwin {
namespace {

// The deposited bead is centred on its path: the fill-weighted centroid across the bead lies on the path
// line, in x for a bead along y and in y for a bead along x, for either direction of travel.
TEST(Deposit, BeadIsCentredOnItsPath) {
  const double s = 2.54;
  for (const bool along_y : {true, false}) {
    for (const double dir : {1.0, -1.0}) {
      const Eigen::Vector3d a = along_y ? Eigen::Vector3d(101.3, 100 - dir * 150, kBeadHeight)
                                        : Eigen::Vector3d(100 - dir * 150, 101.3, kBeadHeight);
      const Eigen::Vector3d b = along_y ? Eigen::Vector3d(101.3, 100 + dir * 150, kBeadHeight)
                                        : Eigen::Vector3d(100 + dir * 150, 101.3, kBeadHeight);
      sim::DepositOptions o;
      o.voxel_size_mm = s;
      const sim::Deposit d = sim::deposit(timed({bead(a, b)}), o);
      double sum = 0, moment = 0;
      for (auto it = d.fill->cbeginValueOn(); it; ++it) {
        const Eigen::Vector3d c = sim::voxel_center_mm(it.getCoord(), s);
        const double along = along_y ? c.y() : c.x();
        if (std::abs(along - 100) > 100) continue;  // away from the ends
        sum += *it;
        moment += *it * (along_y ? c.x() : c.y());
      }
      ASSERT_GT(sum, 0);
      EXPECT_NEAR(moment / sum, 101.3, 0.05 * s)
          << (along_y ? "along y" : "along x") << ", direction " << dir;
    }
  }
}

}  // namespace
}  // namespace beadtwin
