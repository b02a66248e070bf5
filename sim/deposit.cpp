#include "sim/deposit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.hpp"
#include "core/memory.hpp"
#include "core/units.hpp"
#include "sim/bead_sweep.hpp"
#include "sim/fill_writer.hpp"
#include "sim/porosity.hpp"
#include "sim/substrate.hpp"
#include "sim/sweep_plan.hpp"
#include "sim/travel_collision.hpp"
#include "sim/voids.hpp"

namespace beadtwin::sim {

namespace {

// Voxels the sweeps' bounding boxes may visit before the voxel size is called too small for the part: far
// beyond any sensible LSAM job (a 3 m part at 2.5 mm touches tens of millions), well before memory runs out.
constexpr double kMaxVisitedVoxels = 2e9;
// Bounding-box voxels rasterised together: the batch's coverage lists are held in memory at once.
constexpr double kBatchVoxels = 4e6;
constexpr double kMaxVoxelIndex = 1e9;
constexpr int kMaxSupersample = 16;
constexpr std::size_t kMaxListedProblems = 20;
// Voids listed by position (the largest); all of them count in the layers' void volumes.
constexpr std::size_t kMaxListedVoids = 200;

struct Problem {
  SourceLocation where;
  std::string key;
  std::string message;
};

// A problem with an option rather than a move (it has no source location).
Problem option_problem(std::string key, std::string message) {
  Problem p;
  p.key = std::move(key);
  p.message = std::move(message);
  return p;
}

void check_move(const Move& move, std::size_t index, std::vector<Problem>& problems) {
  const auto report = [&](std::string message) {
    problems.push_back(
        {SourceLocation{{}, move.source_line, 0}, fmt::format("move {}", index), std::move(message)});
  };
  if (!std::isfinite(move.volume_mm3) || move.volume_mm3 < 0.0)
    report(fmt::format("volume must be finite and >= 0, got {} mm³", move.volume_mm3));
  if (!move.deposits()) return;
  if (!move.start.allFinite() || !move.end.allFinite())
    report(fmt::format("coordinates must be finite, got start ({}, {}, {}) end ({}, {}, {})", move.start.x(),
                       move.start.y(), move.start.z(), move.end.x(), move.end.y(), move.end.z()));
  if (!std::isfinite(move.layer_height_mm) || move.layer_height_mm <= 0.0)
    report(fmt::format("layer height must be positive on a move that deposits, got {} mm",
                       move.layer_height_mm));
  if (!std::isfinite(move.start_s) || !std::isfinite(move.duration_s) || move.duration_s < 0.0)
    report(fmt::format("timing must be finite with duration >= 0, got start {} s, duration {} s",
                       move.start_s, move.duration_s));
}

// Checks everything before any work and reports every problem found (STYLE rule 7).
void validate(const Toolpath& toolpath, const DepositOptions& options) {
  std::vector<Problem> problems;
  if (!std::isfinite(options.voxel_size_mm) || options.voxel_size_mm < 0.0)
    problems.push_back(option_problem(
        "voxel_size",
        fmt::format("voxel size must be positive (or 0: automatic), got {} mm", options.voxel_size_mm)));
  if (!std::isfinite(options.ooze_time_s) || options.ooze_time_s < 0.0)
    problems.push_back(option_problem(
        "ooze_time", fmt::format("ooze time must be finite and >= 0, got {} s", options.ooze_time_s)));
  if (options.supersample < 1 || options.supersample > kMaxSupersample)
    problems.push_back(option_problem("supersample", fmt::format("supersample must be 1..{}, got {}",
                                                                 kMaxSupersample, options.supersample)));
  for (std::size_t i = 0; i < toolpath.moves.size(); ++i) check_move(toolpath.moves[i], i, problems);
  if (problems.empty()) return;
  if (problems.size() == 1) throw InputError(problems[0].where, problems[0].key, problems[0].message);
  std::string message = fmt::format("{} problems make the toolpath impossible to deposit:", problems.size());
  for (std::size_t i = 0; i < std::min(problems.size(), kMaxListedProblems); ++i)
    message += "\n  " + format_input_error(problems[i].where, problems[i].key, problems[i].message);
  if (problems.size() > kMaxListedProblems)
    message += fmt::format("\n  ... and {} more", problems.size() - kMaxListedProblems);
  throw InputError(problems[0].where, {}, message);
}

double choose_voxel_size(const Toolpath& toolpath, const DepositOptions& options) {
  if (options.voxel_size_mm > 0.0) return options.voxel_size_mm;
  double smallest = std::numeric_limits<double>::infinity();
  for (const Move& move : toolpath.moves)
    if (move.deposits()) smallest = std::min(smallest, move.layer_height_mm);
  // Nothing deposits: the size only labels empty grids.
  return std::isfinite(smallest) ? smallest / 2.0 : 1.0;
}

void check_budget(const std::vector<PlannedSweep>& sweeps, double voxel_size_mm) {
  // Voxel indices are 32-bit: keep well inside them.
  double extent = 0.0;
  for (const PlannedSweep& s : sweeps) {
    const double reach = s.sweep.profile.width_mm();
    extent = std::max({extent, s.sweep.start_xy.cwiseAbs().maxCoeff() + reach,
                       s.sweep.end_xy.cwiseAbs().maxCoeff() + reach, std::abs(s.sweep.start_top_mm) + reach,
                       std::abs(s.sweep.end_top_mm) + reach});
  }
  if (extent / voxel_size_mm > kMaxVoxelIndex)
    throw InputError(
        {}, "voxel_size",
        fmt::format("beads reach {:.6g} mm from the origin, {:.3g} voxels of {} mm: beyond the voxel index "
                    "range ({:.3g}); use a larger voxel size or move the part nearer the origin",
                    extent, extent / voxel_size_mm, voxel_size_mm, kMaxVoxelIndex));
  double visits = 0.0;
  for (const PlannedSweep& s : sweeps) visits += s.sweep.bounding_voxels(voxel_size_mm);
  if (visits > kMaxVisitedVoxels)
    throw InputError(
        {}, "voxel_size",
        fmt::format("voxel size {} mm is too small for this toolpath: its beads would visit about {:.3g} "
                    "voxels (limit {:.3g}); use a larger voxel size",
                    voxel_size_mm, visits, kMaxVisitedVoxels));
}

struct Grids {
  openvdb::FloatGrid::Ptr fill, time;
  openvdb::Int32Grid::Ptr layer, move;
};

Grids make_grids(double voxel_size_mm) {
  Grids g{openvdb::FloatGrid::create(0.0f), openvdb::FloatGrid::create(0.0f), openvdb::Int32Grid::create(-1),
          openvdb::Int32Grid::create(-1)};
  g.fill->setName("fill");
  g.fill->setGridClass(openvdb::GRID_FOG_VOLUME);
  g.time->setName("time");
  g.layer->setName("layer");
  g.move->setName("move");
  const auto transform = deposit_transform(voxel_size_mm);
  g.fill->setTransform(transform);
  g.time->setTransform(transform->copy());
  g.layer->setTransform(transform->copy());
  g.move->setTransform(transform->copy());
  return g;
}

struct LayingTotals {
  double swept_voxels = 0.0;
};

// The table's height: given, or the lowest nominal bead bottom.
double table_height_mm(const Toolpath& toolpath, const DepositOptions& options) {
  if (std::isfinite(options.table_z_mm)) return options.table_z_mm;
  double z = std::numeric_limits<double>::infinity();
  for (const Move& m : toolpath.moves)
    if (m.deposits()) z = std::min(z, std::min(m.start.z(), m.end.z()) - m.layer_height_mm);
  return std::isfinite(z) ? z : 0.0;
}

bool keeps_round(const Move& move, const DepositOptions& options) {
  return options.flattening != Flattening::kNozzle && !move.roller_down;
}

// How high above a bead's top the roller meets material standing in its way: its radius (0 when unknown:
// then a layer height is looked at).
double roller_reach(const DepositOptions& options) {
  return options.flattening == Flattening::kRoller ? 0.5 * options.roller_diameter_mm : 0.0;
}

// Beads no flatter than this fraction of their layer height: below it the roller has ploughed the material
// under it flat, and the bead spreads no further.
constexpr double kMinSquash = 0.25;
// A piece is unsupported when fewer than this fraction of its columns have anything within a layer below.
constexpr double kMinSupported = 0.5;
// Material standing this deep (mean, in layer heights) above a bead's top is in the way of the roller or
// the nozzle; ploughed material above this fraction of a piece's own is reported.
constexpr double kCollisionDepth = 0.25;
constexpr double kPloughShare = 0.02;

// The piece shaped by what lies under it (sim/substrate.hpp). A flattened bead keeps its top at the roller:
// its material first runs into the gaps of the band below, the rest makes a bead in its own layer, flatter
// where material already stands above its nominal bottom. A round bead (roller up) sits on the substrate.
struct Shaped {
  double height_mm = 0.0;  // the bead's height, the gaps it filled included
  bool unsupported = false;
  double over_top_mm = 0.0;
  double gap_volume_mm3 = 0.0;  // what goes into the gaps below
  std::vector<CoverageCell> gap_cells;
  bool bead = true;  // false when the gaps take all of the piece's material
};

Shaped shape_piece(PlannedSweep& p, const Move& move, Substrate& sub, const DepositOptions& options,
                   double voxel_size_mm) {
  Shaped out;
  out.height_mm = p.nominal_height_mm;
  out.over_top_mm = sub.over_top_mm;
  BeadSweep& s = p.sweep;
  if (s.is_puddle()) return out;
  out.unsupported = sub.supported < kMinSupported;
  const double h = p.nominal_height_mm;
  const double length = move.length_mm() * (p.along_end - p.along_start);
  const double area = p.volume_mm3 / length;
  if (keeps_round(move, options)) {
    const double below = out.unsupported ? 0.0 : sub.gap_mm - sub.above_mm;  // how much lower it sits
    const double r = std::sqrt(area / kPi);
    const double lift = 2.0 * r - h - below;
    s.profile = {0.0, r};
    s.start_top_mm += lift;
    s.end_top_mm += lift;
    out.height_mm = 2.0 * r;
    return out;
  }
  if (out.unsupported) return out;
  double room = 0.0;
  for (const CoverageCell& c : sub.gap_cells) room += c.fraction;
  const double voxel_volume = voxel_size_mm * voxel_size_mm * voxel_size_mm;
  out.gap_volume_mm3 = std::min(p.volume_mm3, room * voxel_volume);
  out.gap_cells = std::move(sub.gap_cells);
  const double left = p.volume_mm3 - out.gap_volume_mm3;
  const double footprint = sub.columns * voxel_size_mm * voxel_size_mm;
  const double height = std::clamp(h - sub.above_mm, kMinSquash * h, h);
  out.height_mm = height + (footprint > 0.0 ? out.gap_volume_mm3 / footprint : 0.0);
  if (left <= 1e-9 * p.volume_mm3) {
    out.bead = false;
    return out;
  }
  s.profile = moving_bead_profile(left / length, height);
  return out;
}

struct LayContext {
  const Toolpath& toolpath;
  const DepositOptions& options;
  double voxel_size_mm;
  double table_z_mm;
  FillWriter& writer;
  const openvdb::FloatGrid& fill;
  LayingTotals& totals;
  DefectLog& defects;
  std::vector<LayerDeposit>& layers;
  double ploughed_voxels = 0.0;  // what the last lay_bead pushed above the roller
};

// Puts one piece's material into the grids: first what runs into the gaps below, then the bead, each scaled
// so the cells carry exactly its volume.
void lay_bead(const PlannedSweep& planned, const Move& move, std::vector<CoverageCell>& cells, Shaped& shaped,
              int roller_k, LayContext& c) {
  const double vs = c.voxel_size_mm;
  const double voxel_volume = vs * vs * vs;
  const int spread_radius = std::max(1, static_cast<int>(std::ceil(planned.sweep.profile.width_mm() / vs)));
  double ploughed = 0.0;
  if (shaped.gap_volume_mm3 > 0.0) {
    double room = 0.0;
    const auto middle = static_cast<float>(0.5 * (planned.along_start + planned.along_end));
    for (CoverageCell& cell : shaped.gap_cells) {
      room += cell.fraction;
      cell.along = middle;
    }
    c.writer.add(shaped.gap_cells, shaped.gap_volume_mm3 / (room * voxel_volume),
                 {move.start_s, move.duration_s, move.layer, static_cast<int>(planned.move)}, spread_radius,
                 1, roller_k);
    ploughed += c.writer.last_ploughed_voxels();
  }
  if (!shaped.bead) {
    c.ploughed_voxels = ploughed;
    return;
  }
  const double bead_volume = planned.volume_mm3 - shaped.gap_volume_mm3;
  double swept = 0.0;
  for (const CoverageCell& cell : cells) swept += cell.fraction;
  c.totals.swept_voxels += swept;
  if (swept <= 0.0) {
    // A bead thinner than the voxel sampling (or cut away entirely at sharp corners): its material goes into
    // the voxel at its middle and spreads from there, so it is still there.
    const BeadSweep& s = planned.sweep;
    const Eigen::Vector2d mid = 0.5 * (s.start_xy + s.end_xy);
    const double z = 0.5 * (s.start_top_mm + s.end_top_mm) - s.profile.radius_mm;
    cells.assign(1, {voxel_containing({mid.x(), mid.y(), z}, vs), 1.0f, 0.5f});
    swept = 1.0;
  }
  // The cells' `along` is along the piece; the time stamp is along the move.
  const double span = planned.along_end - planned.along_start;
  for (CoverageCell& cell : cells)
    cell.along = static_cast<float>(planned.along_start + span * static_cast<double>(cell.along));
  // Squeezing sideways into empty space reaches about half the bead height (the bead's round side).
  const int squeeze_radius =
      std::max(1, static_cast<int>(std::lround(0.5 * planned.sweep.profile.height_mm() / vs)));
  // The excess may run down into the cusps beside the bead, down to its bottom.
  const BeadSweep& sweep = planned.sweep;
  const int floor_k =
      voxel_row_at_or_above(std::min(sweep.start_top_mm, sweep.end_top_mm) - sweep.profile.height_mm(), vs);
  c.writer.add(cells, bead_volume / (swept * voxel_volume),
               {move.start_s, move.duration_s, move.layer, static_cast<int>(planned.move)}, spread_radius,
               squeeze_radius, roller_k, floor_k);
  c.ploughed_voxels = ploughed + c.writer.last_ploughed_voxels();
}

// Travel moves before `move` (back to the previous depositing move) that hit the part.
void check_travels(std::size_t from, std::size_t to, LayContext& c) {
  for (std::size_t i = from; i < to; ++i) {
    const Move& m = c.toolpath.moves[i];
    if (m.kind != MoveKind::kTravel || m.length_mm() <= 0.0) continue;
    const double depth = travel_collision_mm(m, c.fill, c.voxel_size_mm, c.options.nozzle_diameter_mm);
    if (depth <= 0.0) continue;
    c.defects.add({DefectKind::kCollision, m.start, m.layer, i, m.source_line, depth, "travel"});
  }
}

// Lays one toolpath layer's pieces: measures the substrate under all of them first (the deposit as it stood
// before the layer), then rasterises them in parallel batches and lays them in toolpath order, so the result
// does not depend on the number of threads.
void lay_layer(std::vector<PlannedSweep>& sweeps, std::size_t begin, std::size_t end, std::size_t& next_move,
               LayContext& c) {
  const double vs = c.voxel_size_mm;
  const int highest_k = c.writer.highest_k();
  std::vector<Shaped> shaped(end - begin);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i) {
                        PlannedSweep& p = sweeps[i];
                        const Move& move = c.toolpath.moves[p.move];
                        Substrate sub;
                        if (c.options.follow_substrate && !p.sweep.is_puddle())
                          sub = measure_substrate(
                              p.sweep, p.nominal_top_mm, p.nominal_height_mm,
                              keeps_round(move, c.options) ? p.nominal_height_mm : roller_reach(c.options),
                              c.fill, vs, c.table_z_mm, highest_k);
                        shaped[i - begin] = shape_piece(p, move, sub, c.options, vs);
                      }
                    });
  std::vector<std::vector<CoverageCell>> cells;
  std::size_t batch_begin = begin;
  while (batch_begin < end) {
    std::size_t batch_end = batch_begin;
    double batch = 0.0;
    while (batch_end < end && (batch_end == batch_begin || batch < kBatchVoxels))
      batch += sweeps[batch_end++].sweep.bounding_voxels(vs);
    cells.assign(batch_end - batch_begin, {});
    tbb::parallel_for(tbb::blocked_range<std::size_t>(batch_begin, batch_end),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i != r.end(); ++i)
                          if (shaped[i - begin].bead)
                            rasterize(sweeps[i].sweep, vs, c.options.supersample, cells[i - batch_begin]);
                      });
    for (std::size_t i = batch_begin; i < batch_end; ++i) {
      const PlannedSweep& p = sweeps[i];
      const Move& move = c.toolpath.moves[p.move];
      check_travels(next_move, p.move, c);
      next_move = std::max(next_move, p.move + 1);
      const bool rolled = !keeps_round(move, c.options);
      const int roller_k =
          rolled ? voxel_row_at_or_above(p.nominal_top_mm, vs) : std::numeric_limits<int>::max();
      Shaped& sh = shaped[i - begin];
      lay_bead(p, move, cells[i - batch_begin], sh, roller_k, c);
      const double ploughed = c.ploughed_voxels * vs * vs * vs;
      const Eigen::Vector2d at = p.sweep.start_xy;
      const Eigen::Vector3d where(at.x(), at.y(), p.nominal_top_mm);
      const double plan_length = (p.sweep.end_xy - p.sweep.start_xy).norm();
      if (move.layer >= 0 && static_cast<std::size_t>(move.layer) < c.layers.size()) {
        LayerDeposit& l = c.layers[static_cast<std::size_t>(move.layer)];
        l.plough_volume_mm3 += ploughed;
        l.mean_bead_height_mm += sh.height_mm * plan_length;  // divided by the length at the end
        if (sh.unsupported) l.unsupported_length_mm += plan_length;
      }
      if (ploughed > kPloughShare * p.volume_mm3)
        c.defects.note(DefectKind::kPlough, i, p.move, move, where, ploughed, true);
      if (sh.unsupported) c.defects.note(DefectKind::kUnsupported, i, p.move, move, where, plan_length, true);
      if (sh.over_top_mm > kCollisionDepth * p.nominal_height_mm)
        c.defects.note(DefectKind::kCollision, i, p.move, move, where, sh.over_top_mm, false);
    }
    batch_begin = batch_end;
  }
}

// Lays every piece, layer by layer (a run of consecutive pieces of one toolpath layer).
LayingTotals lay_beads(const Toolpath& toolpath, std::vector<PlannedSweep>& sweeps,
                       const DepositOptions& options, double voxel_size_mm, FillWriter& writer,
                       const openvdb::FloatGrid& fill, DefectLog& defects,
                       std::vector<LayerDeposit>& layers) {
  LayingTotals totals;
  LayContext c{toolpath, options, voxel_size_mm, table_height_mm(toolpath, options), writer, fill,
               totals,   defects, layers};
  std::size_t next_move = 0;
  std::size_t begin = 0;
  while (begin < sweeps.size()) {
    const int layer = toolpath.moves[sweeps[begin].move].layer;
    std::size_t end = begin + 1;
    while (end < sweeps.size() && toolpath.moves[sweeps[end].move].layer == layer) ++end;
    lay_layer(sweeps, begin, end, next_move, c);
    begin = end;
    if (options.progress) options.progress(static_cast<double>(begin) / static_cast<double>(sweeps.size()));
  }
  check_travels(next_move, toolpath.moves.size(), c);
  return totals;
}

double widest_nominal_bead(const Toolpath& toolpath) {
  double widest = 0.0;
  for (const Move& m : toolpath.moves)
    if (m.deposits()) widest = std::max(widest, std::max(m.bead_width_mm, m.layer_height_mm));
  return widest;
}

// Active voxels per voxel of material: the partly filled skin and the material pushed aside.
constexpr double kActivePerMaterialVoxel = 1.3;

// The active voxels the deposit of `toolpath` is expected to make at `voxel_size_mm`.
double planned_voxels(const Toolpath& toolpath, double voxel_size_mm) {
  return toolpath.commanded_volume_mm3() * kActivePerMaterialVoxel / std::pow(voxel_size_mm, 3);
}

// The memory a run will take at a voxel size: the deposit's grids and what the stages after it build from
// them while they are held.
MemoryCost run_cost(const Toolpath& toolpath, const DepositOptions& options, double voxel_size_mm) {
  return deposit_cost(toolpath, voxel_size_mm).scaled(1.0 + options.later_bytes_per_deposit_byte);
}

// The voxel size the deposit uses: the one asked for, which must fit the memory budget (checked before any
// voxel is written: over it, the run stops with a size that fits), or, when none is asked for, half the
// smallest layer height, made coarser when that would not fit.
double settle_voxel_size(const Toolpath& toolpath, const DepositOptions& options, Deposit& out) {
  const double chosen = choose_voxel_size(toolpath, options);
  const double budget = memory_budget_bytes(options.memory_budget_bytes);
  const MemoryCost cost = run_cost(toolpath, options, chosen);
  out.memory_estimate_bytes = cost.bytes();
  if (cost.bytes() <= budget) return chosen;
  const double size = fitting_voxel_mm(cost, chosen, budget);
  if (options.voxel_size_mm > 0.0)
    throw InputError(
        {}, "voxel_size",
        fmt::format("voxel size {} mm needs about {:.1f} GB for this toolpath ({:.3g} voxels), over the "
                    "memory budget of {:.1f} GB; use a voxel size of {} mm or more, or raise the budget",
                    chosen, cost.bytes() / 1e9, planned_voxels(toolpath, chosen), budget / 1e9, size));
  out.notes.push_back(
      fmt::format("voxel size {} mm (half the smallest layer height) would need about {:.1f} GB, "
                  "over the memory budget of {:.1f} GB: {} mm used instead",
                  chosen, cost.bytes() / 1e9, budget / 1e9, size));
  out.memory_estimate_bytes = run_cost(toolpath, options, size).bytes();
  return size;
}

// Per-layer figures once everything is laid.
void summarise_layers(const Toolpath& toolpath, const std::vector<PlannedSweep>& sweeps, Deposit& out) {
  std::vector<double> length(out.layers.size(), 0.0);
  for (const PlannedSweep& p : sweeps) {
    const int layer = toolpath.moves[p.move].layer;
    if (layer >= 0 && static_cast<std::size_t>(layer) < length.size())
      length[static_cast<std::size_t>(layer)] += (p.sweep.end_xy - p.sweep.start_xy).norm();
  }
  for (std::size_t i = 0; i < out.layers.size(); ++i) {
    LayerDeposit& l = out.layers[i];
    const ToolpathLayer& tl = toolpath.layers[i];
    for (std::size_t m = tl.first_move; m < tl.end_move; ++m)
      l.commanded_volume_mm3 += toolpath.moves[m].volume_mm3;
    if (tl.outline_area_mm2 > 0.0 && tl.height_mm > 0.0)
      l.fill_ratio = l.commanded_volume_mm3 / (tl.outline_area_mm2 * tl.height_mm);
    l.mean_bead_height_mm = length[i] > 0.0 ? l.mean_bead_height_mm / length[i] : tl.height_mm;
    out.plough_volume_mm3 += l.plough_volume_mm3;
    out.unsupported_length_mm += l.unsupported_length_mm;
  }
}

int widest_bead_voxels(const std::vector<PlannedSweep>& sweeps, double voxel_size_mm) {
  double widest = 0.0;
  for (const PlannedSweep& s : sweeps) widest = std::max(widest, s.sweep.profile.width_mm());
  return std::max(1, static_cast<int>(std::ceil(widest / voxel_size_mm)));
}

}  // namespace

openvdb::math::Transform::Ptr deposit_transform(double voxel_size_mm) {
  BT_CHECK_OP(voxel_size_mm, >, 0.0);
  auto transform = openvdb::math::Transform::createLinearTransform(voxel_size_mm);
  transform->postTranslate(openvdb::Vec3d(0.5 * voxel_size_mm));
  return transform;
}

openvdb::Coord voxel_containing(const Eigen::Vector3d& point_mm, double voxel_size_mm) {
  const auto index = [voxel_size_mm](double v) {
    return static_cast<openvdb::Int32>(std::floor(v / voxel_size_mm));
  };
  return {index(point_mm.x()), index(point_mm.y()), index(point_mm.z())};
}

Eigen::Vector3d voxel_center_mm(const openvdb::Coord& ijk, double voxel_size_mm) {
  return Eigen::Vector3d(ijk.x() + 0.5, ijk.y() + 0.5, ijk.z() + 0.5) * voxel_size_mm;
}

int voxel_row_at_or_above(double z_mm, double voxel_size_mm) {
  return static_cast<int>(std::ceil(z_mm / voxel_size_mm - 0.5));
}

// Bytes per active voxel: four grids of four bytes in leaf nodes that a thin shell fills about half, the
// tree above them, and the batches of coverage cells.
constexpr double kBytesPerVoxel = 50.0;
// Bytes a made deposit holds per byte of its grids (Grid::memUsage): what its work left to the allocator.
// Bytes a face of its surface takes once meshed, in everything the run builds from it. Both measured on
// whole runs (docs/RELIABILITY.md).
constexpr double kHeldPerGridByte = 1.6;
constexpr double kSurfaceBytesPerFace = 280.0;

MemoryCost deposit_cost(const Toolpath& toolpath, double voxel_size_mm) {
  return {.volume_bytes = planned_voxels(toolpath, voxel_size_mm) * kBytesPerVoxel};
}

MemoryCost deposit_cost(const Deposit& deposit) {
  const auto bytes = [](const auto& grid) { return grid ? static_cast<double>(grid->memUsage()) : 0.0; };
  return {.volume_bytes =
              kHeldPerGridByte * (bytes(deposit.fill) + bytes(deposit.time) + bytes(deposit.layer) +
                                  bytes(deposit.move) + bytes(deposit.gaps))};
}

MemoryCost surface_cost(const Deposit& deposit) {
  return {.surface_bytes = kSurfaceBytesPerFace * static_cast<double>(deposit.surface_faces)};
}

double deposit_voxel_size_mm(const Toolpath& toolpath, const DepositOptions& options) {
  validate(toolpath, options);
  Deposit unused;
  return settle_voxel_size(toolpath, options, unused);
}

Deposit deposit(const Toolpath& toolpath, const DepositOptions& options) {
  openvdb::initialize();
  validate(toolpath, options);

  Deposit out;
  out.commanded_volume_mm3 = toolpath.commanded_volume_mm3();
  out.voxel_size_mm = settle_voxel_size(toolpath, options, out);
  const double vs = out.voxel_size_mm;
  const double voxel_volume = vs * vs * vs;
  SweepPlanOptions plan;
  plan.round_free_ends = options.round_free_ends;
  if (options.follow_substrate)
    plan.max_piece_mm = std::max(vs, options.piece_bead_widths * widest_nominal_bead(toolpath));
  plan.ooze_time_s = options.ooze_time_s;
  std::vector<PlannedSweep> sweeps = plan_sweeps(toolpath, plan);
  for (const PlannedSweep& p : sweeps)
    if (p.ooze) out.ooze_volume_mm3 += p.volume_mm3;
  check_budget(sweeps, vs);

  Grids grids = make_grids(vs);
  out.fill = grids.fill;
  out.time = grids.time;
  out.layer = grids.layer;
  out.move = grids.move;
  out.layers.resize(toolpath.layers.size());
  FillWriter writer(*grids.fill, *grids.time, *grids.layer, *grids.move);
  DefectLog defects;
  if (options.flattening != Flattening::kNozzle && options.roller_width_mm > 0.0)
    roller_corners(toolpath, options.roller_width_mm, defects);
  const LayingTotals totals =
      lay_beads(toolpath, sweeps, options, vs, writer, *grids.fill, defects, out.layers);
  out.defects = defects.take();
  std::stable_sort(out.defects.begin(), out.defects.end(),
                   [](const Defect& a, const Defect& b) { return a.move < b.move; });

  out.gaps = openvdb::MaskGrid::create();
  out.gaps->setTransform(deposit_transform(vs));
  const Porosity porosity = measure_porosity(*grids.fill, widest_bead_voxels(sweeps, vs), out.gaps.get());
  out.swept_volume_mm3 = totals.swept_voxels * voxel_volume;
  out.redistributed_volume_mm3 = writer.redistributed_voxels() * voxel_volume;
  out.deposited_volume_mm3 = porosity.material_voxels * voxel_volume;
  out.void_volume_mm3 = porosity.void_voxels * voxel_volume;
  out.porosity = porosity.fraction();
  out.active_voxels = static_cast<std::size_t>(grids.fill->activeVoxelCount());
  out.surface_faces = porosity.surface_faces;
  BT_CHECK_OP(out.active_voxels, ==, static_cast<std::size_t>(grids.layer->activeVoxelCount()));
  summarise_layers(toolpath, sweeps, out);
  VoidsFound voids = locate_voids(*out.gaps, out, toolpath, voxel_volume, kMaxListedVoids);
  out.void_count = voids.count;
  for (std::size_t i = 0; i < out.layers.size(); ++i)
    out.layers[i].void_volume_mm3 = voids.layer_volume_mm3[i];
  out.defects.insert(out.defects.end(), voids.defects.begin(), voids.defects.end());
  for (Defect& d : out.defects) d.detail = describe(d);
  return out;
}

std::string_view to_string(Flattening flattening) {
  switch (flattening) {
    case Flattening::kNozzle:
      return "nozzle";
    case Flattening::kRoller:
      return "roller";
    case Flattening::kTamper:
      return "tamper";
  }
  return "?";
}

namespace {

// The deposit's fill on the voxels where `keep(ijk)` holds.
template <class Keep>
openvdb::FloatGrid::Ptr fill_where(const Deposit& deposit, const Keep& keep) {
  openvdb::FloatGrid::Ptr out = openvdb::FloatGrid::create(deposit.fill->background());
  out->setTransform(deposit.fill->transform().copy());
  out->setName(deposit.fill->getName());
  auto out_at = out->getAccessor();
  for (auto it = deposit.fill->cbeginValueOn(); it; ++it)
    if (keep(it.getCoord())) out_at.setValue(it.getCoord(), *it);
  return out;
}

}  // namespace

openvdb::FloatGrid::Ptr fill_up_to_layer(const Deposit& deposit, int last_layer) {
  BT_CHECK(deposit.fill != nullptr && deposit.layer != nullptr);
  auto layer_at = deposit.layer->getConstAccessor();
  return fill_where(deposit, [&](const openvdb::Coord& ijk) {
    const int layer = layer_at.getValue(ijk);
    return layer >= 0 && layer <= last_layer;
  });
}

openvdb::FloatGrid::Ptr fill_up_to_time(const Deposit& deposit, double time_s) {
  BT_CHECK(deposit.fill != nullptr && deposit.time != nullptr);
  auto time_at = deposit.time->getConstAccessor();
  return fill_where(deposit, [&](const openvdb::Coord& ijk) { return time_at.getValue(ijk) <= time_s; });
}

}  // namespace beadtwin::sim
