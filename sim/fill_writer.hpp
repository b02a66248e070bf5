// Material into the deposit's grids, conserved (docs/physics.md, deposition).
//
// A move's material is spread over the voxels its bead covers, in proportion to the covered fraction. No
// voxel holds more than its own volume: what would overfill one is pushed on, and kept local — first into
// the gaps between beads already laid nearby (voxels partly full, within a bead width), then into empty
// space right beside it (the bead squeezes a little wider), then upward (the roller ploughs). Each ring of
// neighbours shares the excess in proportion to its free room, so it spreads evenly to every side. Nothing
// is ever dropped, so the grid holds exactly what was added, to float rounding. A voxel is stamped with the
// time, layer and index of the move that brought it at least as much material as it already held: the move
// whose material it mostly is. A later move that tops it up with less leaves the stamp, so a bead's cells,
// a layer's colour and the part as it stood after a layer follow the material, not the last touch (where
// neighbouring beads overlap, a later bead tops up the earlier one's round corners; stamped by the last
// touch, its cells wrapped round them and the two beads shared twice the contact they have, the more so
// the finer the voxels).
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <openvdb/openvdb.h>

#include "sim/bead_sweep.hpp"

namespace beadtwin::sim {

// What a voxel is stamped with when a move puts at least as much material into it as it held.
struct MoveStamp {
  double start_s = 0.0;     // time the move starts
  double duration_s = 0.0;  // the voxel at `along` gets start_s + along · duration_s
  int layer = -1;
  int move = -1;  // index into Toolpath::moves
};

// Writes moves' material into the deposit's four grids, conserving it. Not thread-safe: one writer, one
// thread.
class FillWriter {
 public:
  // The four grids share one active topology: a voxel is active iff it holds material.
  FillWriter(openvdb::FloatGrid& fill, openvdb::FloatGrid& time, openvdb::Int32Grid& layer,
             openvdb::Int32Grid& move);
  ~FillWriter();  // clears the leaves' transient data (SliceMasks)
  FillWriter(const FillWriter&) = delete;
  FillWriter& operator=(const FillWriter&) = delete;

  // Adds `fill_per_fraction` · fraction (in voxel volumes) to every cell. Excess goes into partly filled
  // voxels within `spread_radius` (>= 1) voxels in plan, at its own level and then level by level down to
  // index `floor_k` (the bead's bottom row; none below the overflow's level by default), then into any free
  // voxel within `squeeze_radius` (>= 1) at its own level, then upward.
  // Material pushed into voxels at index k >= `roller_k` (above the roller's gap) counts as ploughed.
  void add(std::span<const CoverageCell> cells, double fill_per_fraction, const MoveStamp& stamp,
           int spread_radius, int squeeze_radius, int roller_k = std::numeric_limits<int>::max(),
           int floor_k = std::numeric_limits<int>::max());
  // Material the last add() pushed above the roller, in voxel volumes.
  double last_ploughed_voxels() const { return ploughed_; }

  // Material moved out of overfull voxels so far, in voxel volumes.
  double redistributed_voxels() const { return redistributed_; }

  // The highest voxel index k at which this writer has put material (no voxel above it holds any of its
  // material); the lowest int when it has put none.
  int highest_k() const { return highest_k_; }

 private:
  struct Overflow {
    openvdb::Coord ijk;
    double excess = 0.0;
    float time_s = 0.0f;
  };

  // Which voxels of each slice of a leaf (its 8×8 voxels at one level; bit 8·(x mod 8) + (y mod 8)) are full
  // and which partly full (a gap), kept as they fill. A leaf's masks are found through its transient data
  // (1 + their index; 0: none yet), a word OpenVDB keeps for its users and never stores.
  struct SliceMasks {
    std::array<std::uint64_t, 8> full{}, gaps{};
  };

  // The fill of one level around an overflowing voxel, read straight from its leaves' buffers. spread()'s
  // lookups are most of a deposit's work: on a large part many overflows read every voxel of every gap ring
  // before finding no room and going up (docs/PERFORMANCE.md). The window looks each leaf up once
  // (an 8×8×8 block with no leaf holds one value throughout, its tile's or the background), so a read is an
  // index into a buffer, and it knows where the level's gaps are and which of its slices are full, so the
  // rings that hold no gap (or lie in full slices alone) are not read at all. Writes go through the accessor,
  // into the same buffers; written() forgets a block that had no leaf, since the write made one.
  class LevelWindow {
   public:
    LevelWindow(const openvdb::FloatGrid::Accessor& fill, const std::vector<SliceMasks>& masks)
        : fill_(fill), masks_(masks) {}
    // Covers the voxels within `radius` (in plan, L1) of `centre` in its level; its leaves are looked up
    // when first read.
    void reset(const openvdb::Coord& centre, int radius);
    // What the window's leaves (all looked up now) say of its rings around `centre`, as they stand.
    struct Rings {
      // Bit r: ring r (the voxels at L1 distance r from the centre) holds a gap. Rings past 63 are not
      // known and must be read.
      std::uint64_t with_gaps = 0;
      int first_room = 0;  // the first ring that reaches a slice not full; the rings inside have no room
      bool holds_gap(int ring) const { return ring > 63 || ((with_gaps >> ring) & 1u) != 0; }
    };
    Rings rings(const openvdb::Coord& centre, int radius);
    // Bit r (1 <= r <= `rings`, at most kNearRings) set: ring r around `centre` holds a gap, as the leaves
    // say now. From the gap masks of the (at most four) blocks the rings reach, each against a mask of the
    // ring's voxels in that block, so rings without a gap are passed over without reading their voxels.
    static constexpr int kNearRings = 4;
    std::uint32_t near_gaps(const openvdb::Coord& centre, int rings);
    float value(int x, int y) {
      const Block& b = block(x, y);
      return b.data ? b.data[((x & 7) << 6) | ((y & 7) << 3) | (k_ & 7)] : b.uniform;
    }
    void written(int x, int y) {
      Block& b = blocks_[index(x, y)];
      if (!b.data) b.looked = 0;
    }

   private:
    struct Block {
      std::uint32_t looked = 0;     // the generation (reset) it was looked up in
      bool full = false;            // every voxel of the block's slice holds at least its volume
      std::uint64_t gaps = 0;       // its voxels that hold material, less than their volume (SliceMasks)
      const float* data = nullptr;  // the leaf's values; none: `uniform` throughout
      float uniform = 0.0f;
    };
    std::size_t index(int x, int y) const {
      return static_cast<std::size_t>((y >> 3) - by0_) * static_cast<std::size_t>(across_) +
             static_cast<std::size_t>((x >> 3) - bx0_);
    }
    const Block& block(int x, int y) {
      const Block& b = blocks_[index(x, y)];
      return b.looked == generation_ ? b : look(x, y);
    }
    const Block& look(int x, int y);
    // The leaves found by earlier looks, kept across resets (a spread's window overlaps the last one's), by
    // their origin / 8 in a small table indexed by its low bits: a leaf, once made, stays where it is and
    // keeps its buffer while the writer lives (its masks are read afresh each look). Leaves not found are
    // not kept: a write may make them.
    struct Known {
      openvdb::Coord block{std::numeric_limits<int>::min()};  // the leaf's origin / 8
      const openvdb::FloatTree::LeafNodeType* leaf = nullptr;
      const float* data = nullptr;
    };
    static constexpr int kKnownBits = 4;  // 16 x 16 blocks in plan, a slab of them deep
    const openvdb::FloatGrid::Accessor& fill_;
    const std::vector<SliceMasks>& masks_;
    int bx0_ = 0, by0_ = 0, k_ = 0;  // the first block's index (voxel index / 8) in x and y; the level
    int across_ = 0;                 // blocks across, each way
    std::uint32_t generation_ = 0;   // of the reset; blocks looked up in an earlier one are forgotten
    std::vector<Block> blocks_;
    std::array<Known, std::size_t{1} << (2 * kKnownBits)> known_{};
  };

  // Writes `value` into the fill at `ijk`, which held `before`, counting the voxel full if it now is.
  void set_fill(const openvdb::Coord& ijk, float before, float value);
  // Stamps `ijk` with `of` (and `time_s`) if `added`, the material the move just put into it, is at least
  // the `held` it had before (voxel volumes): the voxel is the move's material.
  void claim(const openvdb::Coord& ijk, double held, double added, float time_s, const MoveStamp& of);
  void spread(const Overflow& overflow, const MoveStamp& of, int spread_radius, int squeeze_radius);

  openvdb::FloatGrid::Accessor fill_;
  openvdb::FloatGrid::Accessor time_;
  openvdb::Int32Grid::Accessor layer_;
  openvdb::Int32Grid::Accessor move_;
  std::vector<SliceMasks> masks_;
  LevelWindow window_{fill_, masks_};
  std::vector<Overflow> overflow_;
  std::vector<std::pair<openvdb::Coord, float>> ring_cells_;  // spread()'s ring: voxel, fill held; kept
  double redistributed_ = 0.0;
  double ploughed_ = 0.0;
  int roller_k_ = std::numeric_limits<int>::max();
  int floor_k_ = std::numeric_limits<int>::max();
  int highest_k_ = std::numeric_limits<int>::min();
};

}  // namespace beadtwin::sim
