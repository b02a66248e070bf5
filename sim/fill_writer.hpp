// Material into the deposit's grids, conserved (docs/physics.md, deposition).
//
// A move's material is spread over the voxels its bead covers, in proportion to the covered fraction. No
// voxel holds more than its own volume: what would overfill one is pushed on, and kept local — first into
// the gaps between beads already laid nearby (voxels partly full, within a bead width), then into empty
// space right beside it (the bead squeezes a little wider), then upward (the roller ploughs). Each ring of
// neighbours shares the excess in proportion to its free room, so it spreads evenly to every side. Nothing
// is ever dropped, so the grid holds exactly what was added, to float rounding. Each voxel that receives
// material is stamped with the time, layer and index of the move.
#pragma once

#include <limits>
#include <span>
#include <vector>

#include <openvdb/openvdb.h>

#include "sim/bead_sweep.hpp"

namespace beadtwin::sim {

struct MoveStamp {
  double start_s = 0.0;     // time the move starts
  double duration_s = 0.0;  // the voxel at `along` gets start_s + along · duration_s
  int layer = -1;
  int move = -1;  // index into Toolpath::moves
};

class FillWriter {
 public:
  // The four grids share one active topology: a voxel is active iff it holds material.
  FillWriter(openvdb::FloatGrid& fill, openvdb::FloatGrid& time, openvdb::Int32Grid& layer,
             openvdb::Int32Grid& move);

  // Adds `fill_per_fraction` · fraction (in voxel volumes) to every cell. Excess goes into partly filled
  // neighbours within `spread_radius` (>= 1) voxels in plan, then into any free voxel within
  // `squeeze_radius` (>= 1), then upward.
  // Material pushed into voxels at index k >= `roller_k` (above the roller's gap) counts as ploughed.
  void add(std::span<const CoverageCell> cells, double fill_per_fraction, const MoveStamp& stamp,
           int spread_radius, int squeeze_radius, int roller_k = std::numeric_limits<int>::max());
  // Material the last add() pushed above the roller, in voxel volumes.
  double last_ploughed_voxels() const { return ploughed_; }

  // Material moved out of overfull voxels so far, in voxel volumes.
  double redistributed_voxels() const { return redistributed_; }

 private:
  struct Overflow {
    openvdb::Coord ijk;
    double excess = 0.0;
    float time_s = 0.0f;
  };

  void stamp(const openvdb::Coord& ijk, float time_s, const MoveStamp& of);
  void spread(const Overflow& overflow, const MoveStamp& of, int spread_radius, int squeeze_radius);

  openvdb::FloatGrid::Accessor fill_;
  openvdb::FloatGrid::Accessor time_;
  openvdb::Int32Grid::Accessor layer_;
  openvdb::Int32Grid::Accessor move_;
  std::vector<Overflow> overflow_;
  double redistributed_ = 0.0;
  double ploughed_ = 0.0;
  int roller_k_ = std::numeric_limits<int>::max();
};

}  // namespace beadtwin::sim
