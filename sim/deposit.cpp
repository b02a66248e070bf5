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
#include "sim/bead_sweep.hpp"
#include "sim/fill_writer.hpp"
#include "sim/porosity.hpp"
#include "sim/sweep_plan.hpp"

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
  openvdb::Int32Grid::Ptr layer;
};

Grids make_grids(double voxel_size_mm) {
  Grids g{openvdb::FloatGrid::create(0.0f), openvdb::FloatGrid::create(0.0f), openvdb::Int32Grid::create(-1)};
  g.fill->setName("fill");
  g.fill->setGridClass(openvdb::GRID_FOG_VOLUME);
  g.time->setName("time");
  g.layer->setName("layer");
  const auto transform = deposit_transform(voxel_size_mm);
  g.fill->setTransform(transform);
  g.time->setTransform(transform->copy());
  g.layer->setTransform(transform->copy());
  return g;
}

struct LayingTotals {
  double swept_voxels = 0.0;
};

// Puts one move's material into the grids: scaled so the covered fractions carry exactly its volume.
void lay_bead(const PlannedSweep& planned, const Move& move, std::vector<CoverageCell>& cells,
              double voxel_size_mm, FillWriter& writer, LayingTotals& totals) {
  const double voxel_volume = voxel_size_mm * voxel_size_mm * voxel_size_mm;
  double swept = 0.0;
  for (const CoverageCell& c : cells) swept += c.fraction;
  totals.swept_voxels += swept;
  if (swept <= 0.0) {
    // A bead thinner than the voxel sampling (or cut away entirely at sharp corners): its material goes into
    // the voxel at its middle and spreads from there, so it is still there.
    const BeadSweep& s = planned.sweep;
    const Eigen::Vector2d mid = 0.5 * (s.start_xy + s.end_xy);
    const double z = 0.5 * (s.start_top_mm + s.end_top_mm) - s.profile.radius_mm;
    cells.assign(1, {voxel_containing({mid.x(), mid.y(), z}, voxel_size_mm), 1.0f, 0.5f});
    swept = 1.0;
  }
  const int spread_radius =
      std::max(1, static_cast<int>(std::ceil(planned.sweep.profile.width_mm() / voxel_size_mm)));
  // Squeezing sideways into empty space reaches about half the bead height (the bead's round side).
  const int squeeze_radius =
      std::max(1, static_cast<int>(std::lround(0.5 * planned.sweep.profile.height_mm() / voxel_size_mm)));
  writer.add(cells, move.volume_mm3 / (swept * voxel_volume), {move.start_s, move.duration_s, move.layer},
             spread_radius, squeeze_radius);
}

// Rasterises the sweeps in parallel, batch by batch, and lays them in toolpath order, so the result does
// not depend on the number of threads.
LayingTotals lay_beads(const Toolpath& toolpath, const std::vector<PlannedSweep>& sweeps,
                       const DepositOptions& options, double voxel_size_mm, FillWriter& writer) {
  LayingTotals totals;
  std::vector<std::vector<CoverageCell>> cells;
  std::size_t begin = 0;
  while (begin < sweeps.size()) {
    std::size_t end = begin;
    double batch = 0.0;
    while (end < sweeps.size() && (end == begin || batch < kBatchVoxels))
      batch += sweeps[end++].sweep.bounding_voxels(voxel_size_mm);
    cells.assign(end - begin, {});
    tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i != r.end(); ++i)
                          rasterize(sweeps[i].sweep, voxel_size_mm, options.supersample, cells[i - begin]);
                      });
    for (std::size_t i = begin; i < end; ++i)
      lay_bead(sweeps[i], toolpath.moves[sweeps[i].move], cells[i - begin], voxel_size_mm, writer, totals);
    begin = end;
  }
  return totals;
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

Deposit deposit(const Toolpath& toolpath, const DepositOptions& options) {
  openvdb::initialize();
  validate(toolpath, options);

  Deposit out;
  out.commanded_volume_mm3 = toolpath.commanded_volume_mm3();
  out.voxel_size_mm = choose_voxel_size(toolpath, options);
  const double vs = out.voxel_size_mm;
  const double voxel_volume = vs * vs * vs;
  const std::vector<PlannedSweep> sweeps = plan_sweeps(toolpath, options.round_free_ends);
  check_budget(sweeps, vs);

  Grids grids = make_grids(vs);
  out.fill = grids.fill;
  out.time = grids.time;
  out.layer = grids.layer;
  FillWriter writer(*grids.fill, *grids.time, *grids.layer);
  const LayingTotals totals = lay_beads(toolpath, sweeps, options, vs, writer);

  const Porosity porosity = measure_porosity(*grids.fill, widest_bead_voxels(sweeps, vs));
  out.swept_volume_mm3 = totals.swept_voxels * voxel_volume;
  out.redistributed_volume_mm3 = writer.redistributed_voxels() * voxel_volume;
  out.deposited_volume_mm3 = porosity.material_voxels * voxel_volume;
  out.void_volume_mm3 = porosity.void_voxels * voxel_volume;
  out.porosity = porosity.fraction();
  out.active_voxels = static_cast<std::size_t>(grids.fill->activeVoxelCount());
  BT_CHECK_OP(out.active_voxels, ==, static_cast<std::size_t>(grids.layer->activeVoxelCount()));
  return out;
}

}  // namespace beadtwin::sim
