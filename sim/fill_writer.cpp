#include "sim/fill_writer.hpp"

#include <algorithm>
#include <cstdlib>

#include "core/error.hpp"

namespace beadtwin::sim {

FillWriter::FillWriter(openvdb::FloatGrid& fill, openvdb::FloatGrid& time, openvdb::Int32Grid& layer,
                       openvdb::Int32Grid& move)
    : fill_(fill.getAccessor()),
      time_(time.getAccessor()),
      layer_(layer.getAccessor()),
      move_(move.getAccessor()) {}

void FillWriter::stamp(const openvdb::Coord& ijk, float time_s, const MoveStamp& of) {
  time_.setValue(ijk, time_s);
  layer_.setValue(ijk, of.layer);
  move_.setValue(ijk, of.move);
}

void FillWriter::add(std::span<const CoverageCell> cells, double fill_per_fraction,
                     const MoveStamp& stamp_of_move, int spread_radius, int squeeze_radius, int roller_k) {
  BT_CHECK_OP(fill_per_fraction, >, 0.0);
  BT_CHECK_OP(spread_radius, >=, 1);
  BT_CHECK_OP(squeeze_radius, >=, 1);
  // Every cell first takes what fits, so the excess of one cell never lands in another cell the same move is
  // about to fill; only then is the excess spread, in the cells' order.
  overflow_.clear();
  ploughed_ = 0.0;
  roller_k_ = roller_k;
  for (const CoverageCell& cell : cells) {
    const double before = fill_.getValue(cell.ijk);
    const double after = before + cell.fraction * fill_per_fraction;
    const auto time_s = static_cast<float>(stamp_of_move.start_s + cell.along * stamp_of_move.duration_s);
    if (before < 1.0) stamp(cell.ijk, time_s, stamp_of_move);
    if (after > 1.0) {
      fill_.setValue(cell.ijk, 1.0f);
      overflow_.push_back({cell.ijk, after - 1.0, time_s});
    } else {
      fill_.setValue(cell.ijk, static_cast<float>(after));
    }
  }
  for (const Overflow& overflow : overflow_) spread(overflow, stamp_of_move, spread_radius, squeeze_radius);
}

void FillWriter::spread(const Overflow& overflow, const MoveStamp& of, int spread_radius,
                        int squeeze_radius) {
  double excess = overflow.excess;
  redistributed_ += excess;
  // The voxels of one ring are offered the excess together, in proportion to their free room, so material
  // squeezed out of a voxel spreads evenly to every side (a fixed visiting order would pile it up on one).
  // `gaps_only` offers only voxels that already hold some material: the gaps between laid beads.
  // Returns true when nothing is left.
  std::vector<std::pair<openvdb::Coord, double>> ring_cells;
  const auto offer_ring = [&](int ring, int k, bool gaps_only) {
    ring_cells.clear();
    double room = 0.0;
    const auto consider = [&](int di, int dj) {
      const openvdb::Coord ijk(overflow.ijk.x() + di, overflow.ijk.y() + dj, k);
      const double held = fill_.getValue(ijk);
      if (held >= 1.0 || (gaps_only && held <= 0.0)) return;
      ring_cells.emplace_back(ijk, 1.0 - held);
      room += 1.0 - held;
    };
    if (ring == 0) {
      consider(0, 0);
    } else {
      for (int di = -ring; di <= ring; ++di) {
        const int dj = ring - std::abs(di);
        consider(di, dj);
        if (dj != 0) consider(di, -dj);
      }
    }
    if (room <= 0.0) return false;
    const double share = std::min(1.0, excess / room);
    for (const auto& [ijk, free] : ring_cells) {
      fill_.setValue(ijk, share >= 1.0 ? 1.0f : static_cast<float>(1.0 - free + share * free));
      stamp(ijk, overflow.time_s, of);
    }
    excess -= share * room;
    if (k >= roller_k_) ploughed_ += share * room;
    return share < 1.0 || excess <= 0.0;
  };
  // First into the gaps between beads already laid nearby; then the bead squeezes a little wider into empty
  // space beside it; what is left rises (the roller ploughs). Keeping the excess local stops it from
  // running ahead into space later beads will need, only to be pushed on again.
  const int k0 = overflow.ijk.z();
  for (int ring = 1; ring <= spread_radius; ++ring)
    if (offer_ring(ring, k0, true)) return;
  for (int ring = 1; ring <= squeeze_radius; ++ring)
    if (offer_ring(ring, k0, false)) return;
  // Above the deposit every voxel is free, so this ends; the bound only guards against a broken grid.
  constexpr int kMaxSlabsUp = 1 << 20;
  for (int up = 1; up < kMaxSlabsUp; ++up) {
    for (int ring = 0; ring <= squeeze_radius; ++ring)
      if (offer_ring(ring, k0 + up, false)) return;
  }
  throw InternalError("fill_writer: could not place " + std::to_string(excess) +
                      " voxel volumes of excess material");
}

}  // namespace beadtwin::sim
