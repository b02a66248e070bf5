// The deposit following what is really under each bead (sim/substrate.hpp), the melt on and off it lays
// (ooze, coast), and the defects it finds.
#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "core/bead.hpp"
#include "core/error.hpp"
#include "core/toolpath.hpp"
#include "core/units.hpp"
#include "sim/bead_section.hpp"
#include "sim/deposit.hpp"
#include "sim/substrate.hpp"
#include "tests/sim/lsam_beads.hpp"

namespace beadtwin {
namespace {

using testing::timed;
using testing::travel;
constexpr double kW = testing::kBeadWidth;
constexpr double kH = testing::kBeadHeight;

// The LSAM bead with `flow_scale` of its material, from program line 100 + its layer.
Move bead(const Eigen::Vector3d& from, const Eigen::Vector3d& to, int layer, double flow_scale = 1.0) {
  Move m = testing::bead(from, to, layer);
  m.volume_mm3 *= flow_scale;
  m.source_line = 100 + layer;
  return m;
}

// The ideal pitch for flattened beads side by side: the section's area over its height (docs/physics.md).
double ideal_pitch() {
  return bead_area_mm2(kW, kH) / kH;
}

// `count` beads 200 mm long at the ideal pitch, `layers` layers; layer `scaled` gets `flow_scale` of the
// material. `outside_in`: each layer lays its outer beads first and works inwards, as boundary passes do
// (each pass a bead along both sides of a wall), so the last bead lands between two laid ones; otherwise
// from one side to the other.
Toolpath block(int count, int layers, int scaled = -1, double flow_scale = 1.0, bool outside_in = false) {
  std::vector<Move> moves;
  Eigen::Vector3d at(0, 0, kH);
  for (int l = 0; l < layers; ++l) {
    const double z = (l + 1) * kH;
    for (int i = 0; i < count; ++i) {
      const int n = outside_in ? (i % 2 == 0 ? i / 2 : count - 1 - i / 2) : i;
      const Eigen::Vector3d a(0, n * ideal_pitch(), z), b(200, n * ideal_pitch(), z);
      moves.push_back(travel(at, a, l));
      moves.push_back(bead(a, b, l, l == scaled ? flow_scale : 1.0));
      at = b;
    }
  }
  return timed(std::move(moves));
}

std::size_t count(const sim::Deposit& d, sim::DefectKind kind) {
  return static_cast<std::size_t>(std::count_if(d.defects.begin(), d.defects.end(),
                                                [&](const sim::Defect& x) { return x.kind == kind; }));
}

// Columns read only up to the deposit's highest material (the writer's highest_k) measure what columns read
// up to the roller's reach measure, bit for bit: above that top there is only air. Beads across, along and
// askew over two under-filled layers (gaps to find), at the next layer and one layer higher up, the roller's
// reach (38 mm, half a 3 in roller) far above both; and at the second layer itself, whose material reaches
// the deposit's top.
TEST(Substrate, ColumnsReadUpToTheDepositsTopMeasureAsWhole) {
  const sim::Deposit d = sim::deposit(block(4, 2, 1, 0.8));
  const double s = d.voxel_size_mm;
  const int top = d.fill->evalActiveVoxelBoundingBox().max().z();
  ASSERT_GT(top, 0);
  const double reach = 0.5 * 3.0 * 25.4;  // mm
  int pieces = 0;
  for (const double above : {0.0, 0.5, 1.0, 2.0})
    for (const auto& [a, b] : {std::pair{Eigen::Vector2d(10, 20), Eigen::Vector2d(190, 20)},
                               std::pair{Eigen::Vector2d(100, -30), Eigen::Vector2d(100, 90)},
                               std::pair{Eigen::Vector2d(20, -10), Eigen::Vector2d(150, 80)}}) {
      sim::BeadSweep sweep;
      sweep.start_xy = a;
      sweep.end_xy = b;
      const double top_mm = (2.0 + above) * kH;
      sweep.start_top_mm = sweep.end_top_mm = top_mm;
      sweep.profile = sim::moving_bead_profile(bead_area_mm2(kW, kH), kH);
      const sim::Substrate whole = sim::measure_substrate(sweep, top_mm, kH, reach, *d.fill, s, 0.0);
      for (const int highest : {top, top + 3}) {
        const sim::Substrate cut = sim::measure_substrate(sweep, top_mm, kH, reach, *d.fill, s, 0.0, highest);
        EXPECT_EQ(cut.gap_mm, whole.gap_mm);
        EXPECT_EQ(cut.above_mm, whole.above_mm);
        EXPECT_EQ(cut.over_top_mm, whole.over_top_mm);
        EXPECT_EQ(cut.supported, whole.supported);
        EXPECT_EQ(cut.columns, whole.columns);
        ASSERT_EQ(cut.gap_cells.size(), whole.gap_cells.size());
        for (std::size_t i = 0; i < cut.gap_cells.size(); ++i) {
          EXPECT_EQ(cut.gap_cells[i].ijk, whole.gap_cells[i].ijk);
          EXPECT_EQ(cut.gap_cells[i].fraction, whole.gap_cells[i].fraction);
        }
      }
      pieces += whole.gap_cells.empty() ? 0 : 1;
      EXPECT_GT(whole.columns, 0);
    }
  EXPECT_GT(pieces, 0);  // some pieces found gaps to fill
  // Cut below the deposit's top a column misses the second layer's material: the rule is only for the true
  // top.
  sim::BeadSweep sweep;
  sweep.start_xy = {10, 20};
  sweep.end_xy = {190, 20};
  sweep.start_top_mm = sweep.end_top_mm = 2.0 * kH;
  sweep.profile = sim::moving_bead_profile(bead_area_mm2(kW, kH), kH);
  EXPECT_LT(sim::measure_substrate(sweep, 2.0 * kH, kH, reach, *d.fill, s, 0.0, 0).above_mm,
            sim::measure_substrate(sweep, 2.0 * kH, kH, reach, *d.fill, s, 0.0).above_mm);
}

// Layers at the ideal pitch leave only the cusps between rounded flanks for the next layer to fill: every
// layer keeps its height (within the few per cent the cusps are of a layer) and nothing ploughs.
TEST(Substrate, LayersAtTheIdealPitchKeepTheirHeight) {
  const sim::Deposit d = sim::deposit(block(5, 4));
  ASSERT_EQ(d.layers.size(), 4u);
  for (const sim::LayerDeposit& l : d.layers) {
    EXPECT_NEAR(l.mean_bead_height_mm / kH, 1.0, 0.03);
    EXPECT_LT(l.plough_volume_mm3, 1e-3 * l.commanded_volume_mm3);
  }
  EXPECT_EQ(count(d, sim::DefectKind::kPlough), 0u);
  EXPECT_EQ(count(d, sim::DefectKind::kUnsupported), 0u);
  EXPECT_LT(std::abs(d.deposited_volume_mm3 / d.commanded_volume_mm3 - 1.0), 0.005);
}

// A wall of six beads at the ideal pitch laid from the outside in, 24 layers, at four voxel rows per layer:
// the excess where neighbours overlap runs down into the cusps under their round sides, so every layer keeps
// its height, its beads touch the layer above over the wall's width and the wall stays on its toolpath.
// (Excess that could only rise above the roller left cusps empty under full rows; the next beads, finding
// material in their band, came out flatter and wider and ploughed more: by layer 24 a third of each layer
// rose above the roller and the beads were 3/4 of their height.)
TEST(Substrate, WallsAtFourVoxelRowsPerLayerKeepTheirLayers) {
  constexpr int kLayers = 24;
  sim::DepositOptions o;
  o.voxel_size_mm = 0.25 * kH;
  const sim::Deposit d = sim::deposit(block(6, kLayers, -1, 1.0, true), o);
  ASSERT_EQ(d.layers.size(), static_cast<std::size_t>(kLayers));
  for (const sim::LayerDeposit& l : d.layers) {
    EXPECT_NEAR(l.mean_bead_height_mm / kH, 1.0, 0.03);
    EXPECT_LT(l.plough_volume_mm3, 0.02 * l.commanded_volume_mm3);
  }
  // The highest full voxels lie in the top layer's band; the wall's rows in the middle of the beads (clear of
  // their ends and the outer flanks) are full but for a few per cent in the cusps, in every layer.
  const double s = d.voxel_size_mm;
  auto fill = d.fill->getConstAccessor();
  int top = 0;
  for (auto it = d.fill->cbeginValueOn(); it; ++it)
    if (*it >= 0.5f) top = std::max(top, it.getCoord().z());
  EXPECT_NEAR((top + 1) * s, kLayers * kH, s);
  const int i = static_cast<int>(std::floor(100.0 / s));
  const int j0 = 0, j1 = static_cast<int>(std::floor(5.0 * ideal_pitch() / s));  // bead centre to centre
  for (int l = 0; l < kLayers; ++l) {
    double held = 0.0;
    int voxels = 0;
    for (int k = 4 * l; k < 4 * l + 4; ++k)
      for (int j = j0; j <= j1; ++j, ++voxels) held += fill.getValue(openvdb::Coord(i, j, k));
    EXPECT_GT(held / voxels, 0.97) << "layer " << l;
  }
}

// An under-extruded layer makes the next layer's beads taller. Layer 0 at 70 % of the
// material has the same beads at the same pitch, so it leaves gaps of 30 % of its volume between them;
// layer 1 runs into them before it makes its own bead. Its material then reaches down into layer 0's band.
TEST(Substrate, UnderExtrudedLayerMakesTheNextLayerTaller) {
  const sim::Deposit d = sim::deposit(block(5, 2, 0, 0.7));
  ASSERT_EQ(d.layers.size(), 2u);
  EXPECT_NEAR(d.layers[0].mean_bead_height_mm, kH, 1e-9);
  // Up to 30 % of a layer can go into the gaps; the flanks of the outer beads are not gaps between beads.
  EXPECT_GT(d.layers[1].mean_bead_height_mm, 1.15 * kH);
  EXPECT_LT(d.layers[1].mean_bead_height_mm, 1.35 * kH);
  int laid_low = 0;  // voxels of layer 0's band that layer 1 put material into
  for (auto it = d.layer->cbeginValueOn(); it; ++it)
    if (*it == 1 && sim::voxel_center_mm(it.getCoord(), d.voxel_size_mm).z() < kH) ++laid_low;
  EXPECT_GT(laid_low, 100);
  EXPECT_LT(std::abs(d.deposited_volume_mm3 / d.commanded_volume_mm3 - 1.0), 0.005);
  // Without following the substrate, layer 1 keeps its nominal height and stays in its own band.
  sim::DepositOptions flat;
  flat.follow_substrate = false;
  const sim::Deposit f = sim::deposit(block(5, 2, 0, 0.7), flat);
  EXPECT_NEAR(f.layers[1].mean_bead_height_mm, kH, 1e-9);
}

// An over-extruded layer (150 %) at the ideal pitch overfills its own band: the roller ploughs the excess
// as it lays it, and the next layer's roller ploughs into what stands above its nominal bottom. Each plough
// is reported with its layer and the program line of the bead that ploughed.
TEST(Substrate, OverExtrudedLayerMakesTheRollerPlough) {
  const sim::Deposit d = sim::deposit(block(5, 2, 0, 1.5));
  EXPECT_GT(d.layers[0].plough_volume_mm3, 0.05 * d.layers[0].commanded_volume_mm3);
  EXPECT_GT(d.layers[1].plough_volume_mm3, 0.05 * d.layers[1].commanded_volume_mm3);
  std::set<int> layers;
  for (const sim::Defect& x : d.defects) {
    if (x.kind != sim::DefectKind::kPlough) continue;
    layers.insert(x.layer);
    EXPECT_EQ(x.source_line, 100 + x.layer);
    EXPECT_NE(x.detail.find("plough"), std::string::npos);
  }
  EXPECT_EQ(layers, (std::set<int>{0, 1}));
  // A flatter, wider bead where material already stands in its band.
  EXPECT_LT(d.layers[1].mean_bead_height_mm, 0.95 * kH);
  EXPECT_LT(std::abs(d.deposited_volume_mm3 / d.commanded_volume_mm3 - 1.0), 0.005);
  // At the right flow nothing ploughs (Substrate.LayersAtTheIdealPitchKeepTheirHeight).
}

// A roller machine with the roller up: the bead keeps a round section of its area A (diameter √(4A/π)),
// sitting on the table, instead of the flattened stadium.
TEST(Substrate, BeadIsRoundWhereTheRollerIsUp) {
  Move m = bead({0, 0, kH}, {200, 0, kH}, 0);
  m.roller_down = false;
  sim::DepositOptions o;
  o.flattening = sim::Flattening::kRoller;
  o.voxel_size_mm = 0.5;
  const sim::Deposit d = sim::deposit(timed({m}), o);
  const double diameter = std::sqrt(4.0 * bead_area_mm2(kW, kH) / kPi);
  double top = 0.0, half_width = 0.0;
  for (auto it = d.fill->cbeginValueOn(); it; ++it) {
    if (*it < 0.5f) continue;
    const Eigen::Vector3d c = sim::voxel_center_mm(it.getCoord(), d.voxel_size_mm);
    top = std::max(top, c.z() + 0.5 * d.voxel_size_mm);
    half_width = std::max(half_width, std::abs(c.y()) + 0.5 * d.voxel_size_mm);
  }
  EXPECT_NEAR(top, diameter, 2 * d.voxel_size_mm);
  EXPECT_NEAR(2 * half_width, diameter, 2 * d.voxel_size_mm);
  EXPECT_GT(diameter, 1.5 * kH);  // clearly not the flattened bead
  // The same bead under the roller is flattened to the layer height.
  m.roller_down = true;
  const sim::Deposit flat = sim::deposit(timed({m}), o);
  double flat_top = 0.0;
  for (auto it = flat.fill->cbeginValueOn(); it; ++it)
    if (*it >= 0.5f) flat_top = std::max(flat_top, sim::voxel_center_mm(it.getCoord(), 0.5).z() + 0.25);
  EXPECT_NEAR(flat_top, kH, 0.5);
  // A machine whose nozzle flattens every bead ignores the roller flag.
  m.roller_down = false;
  sim::DepositOptions half_mm;
  half_mm.voxel_size_mm = 0.5;
  EXPECT_NEAR(sim::deposit(timed({m}), half_mm).layers[0].mean_bead_height_mm, kH, 1e-9);
}

// A bead laid two layers up with nothing under it spans unsupported, for its whole length.
TEST(Defects, UnsupportedSpanIsReportedWithItsLength) {
  std::vector<Move> moves = {bead({0, 0, kH}, {100, 0, kH}, 0), travel({100, 0, kH}, {0, 100, 3 * kH}, 1),
                             bead({0, 100, 3 * kH}, {150, 100, 3 * kH}, 1)};
  const sim::Deposit d = sim::deposit(timed(moves));
  ASSERT_EQ(count(d, sim::DefectKind::kUnsupported), 1u);
  const auto it = std::find_if(d.defects.begin(), d.defects.end(),
                               [](const sim::Defect& x) { return x.kind == sim::DefectKind::kUnsupported; });
  EXPECT_EQ(it->layer, 1);
  EXPECT_EQ(it->move, 2u);
  EXPECT_NEAR(it->size, 150.0, 1e-6);
  EXPECT_NEAR(it->position_mm.y(), 100.0, 1e-9);
  EXPECT_NEAR(d.unsupported_length_mm, 150.0, 1e-6);
}

// A bead laid at the first layer's height beside a stack, in the stack's fourth layer (after its third):
// the nozzle and the roller run into the stack. A 3 in roller meets both layers standing above the bead's
// top (the second and third; the fourth is laid with it); without its diameter only the layer just above
// the top is looked at, so half as deep.
TEST(Defects, BeadBesideATallStackCollides) {
  std::vector<Move> moves;
  for (int l = 0; l < 4; ++l) moves.push_back(bead({0, 0, (l + 1) * kH}, {100, 0, (l + 1) * kH}, l));
  Move late = bead({0, 0.5 * kW, kH}, {100, 0.5 * kW, kH}, 3);
  moves.push_back(late);
  const Toolpath tp = timed(moves);
  const auto depth = [&](double roller_diameter_mm) {
    sim::DepositOptions o;
    o.flattening = sim::Flattening::kRoller;
    o.roller_diameter_mm = roller_diameter_mm;
    double deepest = 0.0;
    for (const sim::Defect& x : sim::deposit(tp, o).defects)
      if (x.kind == sim::DefectKind::kCollision && x.move == 4) deepest = std::max(deepest, x.size);
    return deepest;
  };
  const double near = depth(0.0), roller = depth(3 * kMmPerInch);
  EXPECT_GT(near, 0.25 * kH);
  EXPECT_NEAR(roller / near, 2.0, 0.05);
}

// A memory budget the deposit would exceed stops it before any voxel is written, with a voxel size that
// would fit: memory goes as the inverse cube of the voxel size.
TEST(Deposit, MemoryBudgetStopsWithAVoxelSizeThatFits) {
  sim::DepositOptions o;
  o.voxel_size_mm = 0.5;
  o.memory_budget_bytes = 1e6;
  try {
    sim::deposit(block(5, 2), o);
    FAIL() << "expected the budget to stop the deposit";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "voxel_size");
    const std::string m = e.what();
    EXPECT_NE(m.find("memory budget"), std::string::npos) << m;
    const auto at = m.find("use a voxel size of ");
    ASSERT_NE(at, std::string::npos) << m;
    o.voxel_size_mm = std::stod(m.substr(at + 20));
    EXPECT_GT(o.voxel_size_mm, 0.5);
  }
  const sim::Deposit d = sim::deposit(block(5, 2), o);  // the suggested size fits
  EXPECT_LE(d.memory_estimate_bytes, 1e6);
}

// Ooze: after a melt off with no coast or reverse, the melt under pressure flows on as
// Q0·exp(−t/τ). A 2 s dwell right after gets Q0·τ·(1 − e^(−2/τ)) as a puddle; the travel after it the
// next share, as a string; the bead gives that material up, so the total stays the commanded volume. A
// reverse after the melt off stops it.
TEST(Deposit, OozeAfterMeltOffFollowsThePressureDecay) {
  const auto program = [](bool reverse) {
    std::vector<Move> moves = {bead({0, 0, kH}, {200, 0, kH}, 0)};
    Move off;
    off.kind = MoveKind::kDwell;
    off.event = ExtruderEvent::kMeltOff;
    off.start = off.end = moves[0].end;
    off.layer = 0;
    moves.push_back(off);
    if (reverse) {
      Move r = off;
      r.event = ExtruderEvent::kReverse;
      r.duration_s = 0.5;
      moves.push_back(r);
    }
    Move dwell = off;
    dwell.event = ExtruderEvent::kNone;
    dwell.duration_s = 2.0;
    moves.push_back(dwell);
    moves.push_back(travel(moves[0].end, {200, 100, kH}, 0));
    return timed(moves);
  };
  const double tau = 0.5;  // s: the 2.1 s bead can give up what oozes (at most half of it)
  sim::DepositOptions o;
  o.ooze_time_s = tau;
  const Toolpath tp = program(false);
  const sim::Deposit d = sim::deposit(tp, o);
  const double q0 = tp.moves[0].volume_mm3 / tp.moves[0].duration_s;
  const double dwell_share = q0 * tau * (1.0 - std::exp(-2.0 / tau));
  EXPECT_GT(d.ooze_volume_mm3, dwell_share);          // the travel gets some too
  EXPECT_LT(d.ooze_volume_mm3, q0 * tau * 1.000001);  // never more than the whole decay
  EXPECT_LT(std::abs(d.deposited_volume_mm3 / tp.commanded_volume_mm3() - 1.0), 1e-6);
  // The puddle at the bead's end: material above the bead's top there, which the bead alone leaves empty.
  const auto above_end = [&](const sim::Deposit& x) {
    double sum = 0.0;
    for (auto it = x.fill->cbeginValueOn(); it; ++it) {
      const Eigen::Vector3d c = sim::voxel_center_mm(it.getCoord(), x.voxel_size_mm);
      if (c.x() > 200.0 + 0.5 * kW && c.y() < 0.5 * kW) sum += *it;
    }
    return sum * std::pow(x.voxel_size_mm, 3);
  };
  EXPECT_GT(above_end(d), 0.1 * dwell_share);
  // A string along the travel, beyond the bead's reach.
  int along_travel = 0;
  for (auto it = d.fill->cbeginValueOn(); it; ++it)
    along_travel += sim::voxel_center_mm(it.getCoord(), d.voxel_size_mm).y() > 40.0;
  EXPECT_GT(along_travel, 0);
  // With a reverse after the melt off, no ooze.
  EXPECT_EQ(sim::deposit(program(true), o).ooze_volume_mm3, 0.0);
  // Without an ooze time, none either.
  EXPECT_EQ(sim::deposit(tp).ooze_volume_mm3, 0.0);
}

// The deposit's cost before it is made goes by the material's volume, as the inverse cube of the voxel size;
// after, by its grids; what is meshed from its surface, by its surface's voxel faces. The check before the
// deposit counts the later stages' share per deposit byte on top, as the caller gives it.
TEST(Deposit, CostBeforeAndAfterAndOfTheSurface) {
  const Toolpath tp = block(5, 2);
  const MemoryCost fine = sim::deposit_cost(tp, 1.0), coarse = sim::deposit_cost(tp, 2.0);
  EXPECT_GT(fine.volume_bytes, 0.0);
  EXPECT_DOUBLE_EQ(fine.bytes(), fine.volume_bytes);
  EXPECT_NEAR(coarse.volume_bytes, fine.volume_bytes / 8.0, 1e-9 * fine.volume_bytes);
  sim::DepositOptions o;
  o.voxel_size_mm = 1.0;
  const sim::Deposit d = sim::deposit(tp, o);
  EXPECT_DOUBLE_EQ(d.memory_estimate_bytes, fine.bytes() * (1.0 + o.later_bytes_per_deposit_byte));
  o.later_bytes_per_deposit_byte = 0.0;
  EXPECT_DOUBLE_EQ(sim::deposit(tp, o).memory_estimate_bytes, fine.bytes());
  const MemoryCost held = sim::deposit_cost(d);
  EXPECT_DOUBLE_EQ(held.volume_bytes,
                   1.6 * static_cast<double>(d.fill->memUsage() + d.time->memUsage() + d.layer->memUsage() +
                                             d.move->memUsage() + (d.gaps ? d.gaps->memUsage() : 0)));
  EXPECT_EQ(held.fixed_bytes + held.surface_bytes, 0.0);
  ASSERT_GT(d.surface_faces, 0u);
  EXPECT_DOUBLE_EQ(sim::surface_cost(d).surface_bytes, 280.0 * static_cast<double>(d.surface_faces));
  EXPECT_EQ(sim::surface_cost(d).fixed_bytes + sim::surface_cost(d).volume_bytes, 0.0);
}

// Without a voxel size asked for, one that would not fit the budget is made coarser, and the deposit says so.
TEST(Deposit, AutomaticVoxelSizeFitsTheMemoryBudget) {
  sim::DepositOptions o;
  o.memory_budget_bytes = 2e5;  // the default 2.54 mm voxels need about 0.9 MB
  const sim::Deposit d = sim::deposit(block(5, 2), o);
  EXPECT_GT(d.voxel_size_mm, 0.5 * kH);  // coarser than half the layer height
  EXPECT_LE(d.memory_estimate_bytes, 2e5);
  ASSERT_EQ(d.notes.size(), 1u);
  EXPECT_NE(d.notes[0].find("memory budget"), std::string::npos) << d.notes[0];
  EXPECT_TRUE(sim::deposit(block(5, 2)).notes.empty());
  // Known before the deposit runs (the run makes the CAD's distance on these voxels meanwhile).
  EXPECT_EQ(sim::deposit_voxel_size_mm(block(5, 2), o), d.voxel_size_mm);
  EXPECT_EQ(sim::deposit_voxel_size_mm(block(5, 2)), sim::deposit(block(5, 2)).voxel_size_mm);
  o.voxel_size_mm = 0.5;  // asked for, and over the budget: refused as the deposit refuses it
  EXPECT_THROW((void)sim::deposit_voxel_size_mm(block(5, 2), o), InputError);
}

// Coast: the planner writes a coast as steps whose material falls off linearly to zero
// (slicer/melt_events.hpp); the deposit lays each step's material where it is, so the bead thins out.
TEST(Deposit, CoastThinsTheBeadOut) {
  std::vector<Move> moves = {bead({0, 0, kH}, {100, 0, kH}, 0)};
  const double per_mm = bead_area_mm2(kW, kH);
  for (int k = 0; k < 4; ++k) {  // four 25 mm steps with the exact integral of the linear decay
    Move m = bead({100 + 25.0 * k, 0, kH}, {125 + 25.0 * k, 0, kH}, 0);
    m.feature = Feature::kCoast;
    m.event = ExtruderEvent::kCoast;
    m.volume_mm3 = per_mm * 25.0 * (1.0 - (k + 0.5) / 4.0);
    moves.push_back(m);
  }
  const Toolpath tp = timed(moves);
  const sim::Deposit d = sim::deposit(tp);
  EXPECT_LT(std::abs(d.deposited_volume_mm3 / tp.commanded_volume_mm3() - 1.0), 1e-6);
  // Material per length in slices across the bead: full before the coast, falling through it.
  const auto slice = [&](double x0, double x1) {
    double sum = 0.0;
    for (auto it = d.fill->cbeginValueOn(); it; ++it) {
      const double x = sim::voxel_center_mm(it.getCoord(), d.voxel_size_mm).x();
      if (x >= x0 && x < x1) sum += *it;
    }
    return sum * std::pow(d.voxel_size_mm, 3) / (x1 - x0);
  };
  const double before = slice(40, 60), early = slice(105, 120), late = slice(180, 195);
  EXPECT_NEAR(before / per_mm, 1.0, 0.05);
  EXPECT_LT(early, 0.95 * before);
  EXPECT_LT(late, 0.5 * early);
}

}  // namespace
}  // namespace beadtwin

namespace beadtwin {
namespace {

std::vector<const sim::Defect*> voids_of(const sim::Deposit& d) {
  std::vector<const sim::Defect*> out;
  for (const sim::Defect& x : d.defects)
    if (x.kind == sim::DefectKind::kVoid) out.push_back(&x);
  return out;
}

// Beads at 1.5 times the ideal pitch leave a channel between each pair: voids between fill beads, each
// found between its two beads, in its layer.
TEST(Defects, WidePitchLeavesVoidsBetweenFillBeads) {
  std::vector<Move> moves;
  const double pitch = 1.5 * ideal_pitch();
  Eigen::Vector3d at(0, 0, kH);
  for (int n = 0; n < 4; ++n) {
    const Eigen::Vector3d a(0, n * pitch, kH), b(200, n * pitch, kH);
    moves.push_back(travel(at, a, 0));
    moves.push_back(bead(a, b, 0));
    at = b;
  }
  const sim::Deposit d = sim::deposit(timed(moves));
  const auto voids = voids_of(d);
  ASSERT_EQ(voids.size(), 3u);
  for (const sim::Defect* v : voids) {
    EXPECT_EQ(v->layer, 0);
    EXPECT_NE(v->detail.find("between fill beads"), std::string::npos) << v->detail;
    // In the middle of a channel: half a pitch off a bead's centre line.
    const double offset = std::fmod(v->position_mm.y(), pitch) / pitch;
    EXPECT_NEAR(offset, 0.5, 0.15) << v->position_mm.transpose();
    EXPECT_GT(v->size, 1000.0);  // mm³: a channel 200 mm long
  }
  EXPECT_EQ(d.void_count, 3u);
  // The channels are most of the porosity measure's void; the rest is the not-quite-full voxels beside them.
  EXPECT_LE(d.layers[0].void_volume_mm3, d.void_volume_mm3);
  EXPECT_GT(d.layers[0].void_volume_mm3, 0.8 * d.void_volume_mm3);
  // At the ideal pitch there is no channel.
  EXPECT_TRUE(voids_of(sim::deposit(block(4, 1))).empty());
}

// A zigzag fill inside a boundary loop, its legs steep and wide apart: the V between two legs opening from
// each turn is a void at a zigzag turn; where the legs leave the boundary uncovered, voids between fill and
// boundary.
TEST(Defects, ZigzagTurnsLeaveVoidsAgainstTheBoundary) {
  std::vector<Move> moves;
  const double side = 200.0, inset = 0.5 * (kW + ideal_pitch());
  const Eigen::Vector3d corners[5] = {{0, 0, kH}, {side, 0, kH}, {side, side, kH}, {0, side, kH}, {0, 0, kH}};
  for (int c = 0; c < 4; ++c) {
    Move m = bead(corners[c], corners[c + 1], 0);
    m.feature = Feature::kBoundary;
    m.pass = 0;
    moves.push_back(m);
  }
  moves.push_back(travel(corners[0], {inset, inset, kH}, 0));
  Eigen::Vector3d at(inset, inset, kH);
  const double step = 2.0 * ideal_pitch() * std::sqrt(2.0);
  for (int k = 1; at.x() + step <= side - inset; ++k) {
    const Eigen::Vector3d next(at.x() + step, k % 2 ? side - inset : inset, kH);
    moves.push_back(bead(at, next, 0));
    at = next;
  }
  const sim::Deposit d = sim::deposit(timed(moves));
  const auto voids = voids_of(d);
  ASSERT_FALSE(voids.empty());
  int at_turns = 0, at_boundary = 0;
  for (const sim::Defect* v : voids) {
    at_turns += v->detail.find("at a zigzag turn") != std::string::npos;
    at_boundary += v->detail.find("between fill and boundary") != std::string::npos;
    EXPECT_EQ(v->layer, 0);
  }
  EXPECT_GT(at_boundary, 0);
  EXPECT_GT(at_turns, 0);
}

}  // namespace
}  // namespace beadtwin
