#include "sim/fill_writer.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdlib>

#include "core/error.hpp"

namespace beadtwin::sim {

FillWriter::FillWriter(openvdb::FloatGrid& fill, openvdb::FloatGrid& time, openvdb::Int32Grid& layer,
                       openvdb::Int32Grid& move)
    : fill_(fill.getAccessor()),
      time_(time.getAccessor()),
      layer_(layer.getAccessor()),
      move_(move.getAccessor()) {}

FillWriter::~FillWriter() {
  if (masks_.empty()) return;
  for (auto leaf = fill_.tree().beginLeaf(); leaf; ++leaf) leaf->setTransientData(0);
}

void FillWriter::LevelWindow::reset(const openvdb::Coord& centre, int radius) {
  static_assert(openvdb::FloatTree::LeafNodeType::LOG2DIM == 3, "blocks of 8 voxels");
  bx0_ = (centre.x() - radius) >> 3;
  by0_ = (centre.y() - radius) >> 3;
  k_ = centre.z();
  across_ = std::max(((centre.x() + radius) >> 3) - bx0_, ((centre.y() + radius) >> 3) - by0_) + 1;
  const std::size_t blocks = static_cast<std::size_t>(across_) * static_cast<std::size_t>(across_);
  if (blocks_.size() < blocks) blocks_.resize(blocks);
  if (++generation_ == 0) {  // wrapped: no block may seem looked up
    for (Block& b : blocks_) b.looked = 0;
    generation_ = 1;
  }
}

FillWriter::LevelWindow::Rings FillWriter::LevelWindow::rings(const openvdb::Coord& centre, int radius) {
  Rings rings;
  rings.first_room = radius + 1;
  // Rings near..far may hold a gap (more rings than do is no harm: they are read).
  const auto mark = [&](int near, int far) {
    far = std::min({far, radius, 63});
    if (near > far) return;
    const std::uint64_t upto = far == 63 ? ~std::uint64_t{0} : (std::uint64_t{2} << far) - 1;
    rings.with_gaps |= upto & ~((std::uint64_t{1} << near) - 1);
  };
  for (int by = by0_; by < by0_ + across_; ++by)
    for (int bx = bx0_; bx < bx0_ + across_; ++bx) {
      // The L1 distance from the centre to the nearest voxel of the block.
      const int dx = std::max({0, bx * 8 - centre.x(), centre.x() - (bx * 8 + 7)});
      const int dy = std::max({0, by * 8 - centre.y(), centre.y() - (by * 8 + 7)});
      if (dx + dy > radius) continue;
      const Block& b = block(bx * 8, by * 8);
      if (!b.full) rings.first_room = std::min(rings.first_room, dx + dy);
      // Row by row of the slice (a byte of the mask: one x, y from by·8 up), the rings its gaps span.
      for (int row = 0; row < 8; ++row) {
        const auto bits = static_cast<std::uint8_t>(b.gaps >> (8 * row));
        if (bits == 0) continue;
        const int across = std::abs(bx * 8 + row - centre.x());
        const int low = by * 8 + std::countr_zero(bits) - centre.y();
        const int high = by * 8 + 7 - std::countl_zero(bits) - centre.y();
        const int near = low <= 0 && high >= 0 ? 0 : std::min(std::abs(low), std::abs(high));
        mark(across + near, across + std::max(std::abs(low), std::abs(high)));
      }
    }
  return rings;
}

std::uint32_t FillWriter::LevelWindow::near_gaps(const openvdb::Coord& centre, int rings) {
  BT_CHECK(rings >= 0 && rings <= kNearRings);
  // The voxels of a block at L1 distance r from the centre, by r, the centre's place in its own block and the
  // block's offset from that block (one either way at most, since the rings reach less than a block).
  static const auto masks = [] {
    std::array<std::uint64_t, (kNearRings + 1) * 64 * 9> m{};
    for (int cx = 0; cx < 8; ++cx)
      for (int cy = 0; cy < 8; ++cy)
        for (int dbx = -1; dbx <= 1; ++dbx)
          for (int dby = -1; dby <= 1; ++dby)
            for (int x = 0; x < 8; ++x)
              for (int y = 0; y < 8; ++y) {
                const int r = std::abs(dbx * 8 + x - cx) + std::abs(dby * 8 + y - cy);
                if (r > kNearRings) continue;
                const auto at =
                    static_cast<std::size_t>(((r * 64 + cx * 8 + cy) * 3 + dbx + 1) * 3 + dby + 1);
                m[at] |= std::uint64_t{1} << ((x << 3) | y);
              }
    return m;
  }();
  std::uint32_t out = 0;
  const int cx = centre.x() & 7, cy = centre.y() & 7, cbx = centre.x() >> 3, cby = centre.y() >> 3;
  for (int bx = (centre.x() - rings) >> 3; bx <= (centre.x() + rings) >> 3; ++bx)
    for (int by = (centre.y() - rings) >> 3; by <= (centre.y() + rings) >> 3; ++by) {
      const std::uint64_t gaps = block(bx * 8, by * 8).gaps;
      if (gaps == 0) continue;
      for (int r = 1; r <= rings; ++r) {
        const auto at =
            static_cast<std::size_t>(((r * 64 + cx * 8 + cy) * 3 + bx - cbx + 1) * 3 + by - cby + 1);
        if ((gaps & masks[at]) != 0) out |= 1u << r;
      }
    }
  return out;
}

const FillWriter::LevelWindow::Block& FillWriter::LevelWindow::look(int x, int y) {
  const int bx = (x >> 3) - bx0_, by = (y >> 3) - by0_;
  BT_CHECK(bx >= 0 && by >= 0 && bx < across_ && by < across_);
  Block& b = blocks_[index(x, y)];
  b.looked = generation_;
  const openvdb::Coord ijk(x, y, k_);
  const openvdb::Coord block(x >> 3, y >> 3, k_ >> 3);
  constexpr int kMask = (1 << kKnownBits) - 1;
  Known& known = known_[static_cast<std::size_t>(((block.x() & kMask) << kKnownBits) | (block.y() & kMask))];
  if (known.block != block) {
    const auto* found = fill_.probeConstLeaf(ijk);
    if (found) known = {block, found, found->buffer().data()};
  }
  if (known.block == block) {
    const auto* leaf = known.leaf;
    b.data = known.data;
    const openvdb::Index32 tag = leaf->transientData();
    const auto z = static_cast<std::size_t>(k_ & 7);
    b.full = tag > 0 && masks_[tag - 1].full[z] == ~std::uint64_t{0};
    b.gaps = tag > 0 ? masks_[tag - 1].gaps[z] : 0;
  } else {
    b.data = nullptr;
    b.uniform = fill_.getValue(ijk);
    b.full = b.uniform >= 1.0f;
    b.gaps = b.uniform > 0.0f && b.uniform < 1.0f ? ~std::uint64_t{0} : 0;
  }
  return b;
}

void FillWriter::set_fill(const openvdb::Coord& ijk, float before, float value) {
  auto* leaf = fill_.touchLeaf(ijk);  // as fill_.setValue does, keeping the leaf for the masks
  highest_k_ = std::max(highest_k_, ijk.z());
  leaf->setValueOn(ijk, value);
  // Material is only ever added: a voxel goes from empty to a gap to full, or skips a step.
  const bool was_gap = before > 0.0f && before < 1.0f;
  const bool is_gap = value > 0.0f && value < 1.0f;
  const bool filled = before < 1.0f && value >= 1.0f;
  if (was_gap == is_gap && !filled) return;
  openvdb::Index32 tag = leaf->transientData();
  if (tag == 0) {
    masks_.push_back({});
    tag = static_cast<openvdb::Index32>(masks_.size());
    leaf->setTransientData(tag);
  }
  SliceMasks& m = masks_[tag - 1];
  const auto z = static_cast<std::size_t>(ijk.z() & 7);
  const std::uint64_t bit = std::uint64_t{1} << (((ijk.x() & 7) << 3) | (ijk.y() & 7));
  m.gaps[z] = is_gap ? m.gaps[z] | bit : m.gaps[z] & ~bit;
  if (filled) m.full[z] |= bit;
}

void FillWriter::claim(const openvdb::Coord& ijk, double held, double added, float time_s,
                       const MoveStamp& of) {
  if (added < held) return;
  time_.setValue(ijk, time_s);
  layer_.setValue(ijk, of.layer);
  move_.setValue(ijk, of.move);
}

void FillWriter::add(std::span<const CoverageCell> cells, double fill_per_fraction,
                     const MoveStamp& stamp_of_move, int spread_radius, int squeeze_radius, int roller_k,
                     int floor_k) {
  BT_CHECK_OP(fill_per_fraction, >, 0.0);
  BT_CHECK_OP(spread_radius, >=, 1);
  BT_CHECK_OP(squeeze_radius, >=, 1);
  // Every cell first takes what fits, so the excess of one cell never lands in another cell the same move is
  // about to fill; only then is the excess spread, in the cells' order.
  overflow_.clear();
  ploughed_ = 0.0;
  roller_k_ = roller_k;
  floor_k_ = floor_k;
  for (const CoverageCell& cell : cells) {
    const float held = fill_.getValue(cell.ijk);
    const double before = held;
    const double after = before + cell.fraction * fill_per_fraction;
    const auto time_s = static_cast<float>(stamp_of_move.start_s + cell.along * stamp_of_move.duration_s);
    claim(cell.ijk, before, std::min(after, 1.0) - before, time_s, stamp_of_move);
    if (after > 1.0) {
      set_fill(cell.ijk, held, 1.0f);
      overflow_.push_back({cell.ijk, after - 1.0, time_s});
    } else {
      set_fill(cell.ijk, held, static_cast<float>(after));
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
  std::vector<std::pair<openvdb::Coord, float>>& ring_cells = ring_cells_;
  const int k0 = overflow.ijk.z();
  const int radius = std::max(spread_radius, squeeze_radius);
  window_.reset(overflow.ijk, radius);
  int window_k = k0;
  const auto offer_ring = [&](int ring, int k, bool gaps_only) {
    ring_cells.clear();
    double room = 0.0;
    const auto consider = [&](int di, int dj) {
      const openvdb::Coord ijk(overflow.ijk.x() + di, overflow.ijk.y() + dj, k);
      const float held = k == window_k ? window_.value(ijk.x(), ijk.y()) : fill_.getValue(ijk);
      if (held >= 1.0f || (gaps_only && held <= 0.0f)) return;
      ring_cells.emplace_back(ijk, held);
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
    for (const auto& [ijk, held] : ring_cells) {
      const double free = 1.0 - held;
      set_fill(ijk, held, share >= 1.0 ? 1.0f : static_cast<float>(1.0 - free + share * free));
      if (k == window_k) window_.written(ijk.x(), ijk.y());
      claim(ijk, held, share >= 1.0 ? free : share * free, overflow.time_s, of);
    }
    excess -= share * room;
    if (k >= roller_k_) ploughed_ += share * room;
    return share < 1.0 || excess <= 0.0;
  };
  // The gaps between beads already laid within `spread_radius` of the overflowing voxel, at level k (ring 0
  // too below the overflow's own level). Rings are read only where the leaves say there is a gap: the first
  // few rings, where most spreads end, are asked of their blocks' gap masks ring by ring (near_gaps); the
  // rest by rings(). (This phase only fills gaps: it makes none, so what the leaves said holds.)
  constexpr int kNear = LevelWindow::kNearRings;
  LevelWindow::Rings rings_k0;  // the overflow's own level's, kept for the squeeze below
  const auto fill_gaps = [&](int k) {
    if (k != window_k) {
      window_.reset({overflow.ijk.x(), overflow.ijk.y(), k}, radius);
      window_k = k;
      if (offer_ring(0, k, true)) return true;
    }
    const std::uint32_t near =
        window_.near_gaps({overflow.ijk.x(), overflow.ijk.y(), k}, std::min(kNear, spread_radius));
    for (int ring = 1; ring <= std::min(kNear, spread_radius); ++ring)
      if ((near >> ring & 1u) != 0 && offer_ring(ring, k, true)) return true;
    const LevelWindow::Rings rings = window_.rings({overflow.ijk.x(), overflow.ijk.y(), k}, radius);
    if (k == k0) rings_k0 = rings;
    for (int ring = kNear + 1; ring <= spread_radius; ++ring)
      if (rings.holds_gap(ring) && offer_ring(ring, k, true)) return true;
    return false;
  };
  // First into the gaps between beads already laid nearby, at the overflow's level and then down to the
  // bead's bottom (`floor_k`: the roller or the nozzle presses the bead into the cusps under its round
  // sides); then the bead squeezes a little wider into empty space beside it; what is left rises (the
  // roller ploughs). Keeping the excess local stops it from running ahead into space later beads will need,
  // only to be pushed on again.
  if (fill_gaps(k0)) return;
  for (int k = k0 - 1; k >= floor_k_; --k)
    if (fill_gaps(k)) return;
  if (window_k != k0) {  // the levels below were looked at; the overflow's own is as it was
    window_.reset(overflow.ijk, radius);
    window_k = k0;
  }
  // The rings inside the first that reaches a slice not full offer no room (the gaps filled since do not
  // matter: a ring they filled is read and offers nothing).
  for (int ring = std::max(1, rings_k0.first_room); ring <= squeeze_radius; ++ring)
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
