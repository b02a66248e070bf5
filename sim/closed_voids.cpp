#include "sim/closed_voids.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

namespace beadtwin::sim {
namespace {

using Word = std::uint64_t;
constexpr Word kAll = ~Word{0};

// The bits [a, b) of a row that fall in word w.
Word range_word(std::size_t w, std::size_t a, std::size_t b) {
  const std::size_t lo_bit = std::max(a, 64 * w), hi_bit = std::min(b, 64 * w + 64);
  if (lo_bit >= hi_bit) return Word{0};
  const std::size_t n = hi_bit - lo_bit;
  return (n == 64 ? kAll : (Word{1} << n) - 1) << (lo_bit - 64 * w);
}

// The box as rows along x of bits, row y + ny · z: which voxels are free, and which of those the flood has
// reached.
class RowFlood {
 public:
  explicit RowFlood(const openvdb::CoordBBox& box)
      : lo_(box.min()),
        nx_(static_cast<std::size_t>(box.dim().x())),
        ny_(static_cast<std::size_t>(box.dim().y())),
        nz_(static_cast<std::size_t>(box.dim().z())),
        words_((nx_ + 63) / 64),
        rows_(ny_ * nz_),
        free_(rows_ * words_, 0),
        reached_(rows_ * words_, 0),
        queued_(rows_, 0) {}

  // Free: every voxel of the box but the solid ones (and the padding past nx, which stays 0).
  void mark_free(const openvdb::FloatGrid& fill, const openvdb::CoordBBox& box, double solid_fill) {
    for (std::size_t r = 0; r < rows_; ++r)
      for (std::size_t w = 0; w < words_; ++w) {
        const std::size_t bits = std::min<std::size_t>(64, nx_ - 64 * w);
        free_[r * words_ + w] = bits == 64 ? kAll : (Word{1} << bits) - 1;
      }
    for (auto it = fill.cbeginValueOn(); it; ++it)
      if (*it >= solid_fill && box.isInside(it.getCoord())) {
        const openvdb::Coord c = it.getCoord() - lo_;
        const auto x = static_cast<std::size_t>(c.x());
        free_[(static_cast<std::size_t>(c.y()) + ny_ * static_cast<std::size_t>(c.z())) * words_ + x / 64] &=
            ~(Word{1} << (x % 64));
      }
  }

  // Seeds the flood on the box's open sides.
  void seed_open_sides(bool open_bottom) {
    for (std::size_t z = 0; z < nz_; ++z)
      for (std::size_t y = 0; y < ny_; ++y) {
        const std::size_t r = y + ny_ * z;
        if (y == 0 || y == ny_ - 1 || z == nz_ - 1 || (open_bottom && z == 0)) {
          seed(r, 0, nx_);
        } else {
          seed(r, 0, 1);
          seed(r, nx_ - 1, nx_);
        }
      }
  }

  // Floods until no queued row is left.
  void flood() {
    while (!stack_.empty()) {
      const std::size_t r = stack_.back();
      stack_.pop_back();
      queued_[r] = 0;
      spread_row(r);
    }
  }

  // Sets the free voxels never reached to 1 in `fill`.
  void fill_unreached(openvdb::FloatGrid& fill) const {
    auto acc = fill.getAccessor();
    for (std::size_t r = 0; r < rows_; ++r)
      for (std::size_t w = 0; w < words_; ++w) {
        Word closed = free_[r * words_ + w] & ~reached_[r * words_ + w];
        while (closed != 0) {
          const std::size_t x = 64 * w + static_cast<std::size_t>(std::countr_zero(closed));
          closed &= closed - 1;
          acc.setValue(
              lo_.offsetBy(static_cast<int>(x), static_cast<int>(r % ny_), static_cast<int>(r / ny_)), 1.0f);
        }
      }
  }

 private:
  // Reaches the free voxels [a, b) of row r not reached yet, and queues the row when there were any.
  void seed(std::size_t r, std::size_t a, std::size_t b) {
    bool any = false;
    for (std::size_t w = a / 64; w < words_ && 64 * w < b; ++w) {
      const Word fresh = free_[r * words_ + w] & ~reached_[r * words_ + w] & range_word(w, a, b);
      if (fresh == 0) continue;
      reached_[r * words_ + w] |= fresh;
      any = true;
    }
    if (any && !queued_[r]) {
      queued_[r] = 1;
      stack_.push_back(r);
    }
  }

  // The first voxel of row r from `from` on that is free (or, for !want_free, solid); nx if none is.
  std::size_t next(std::size_t r, std::size_t from, bool want_free) const {
    for (std::size_t w = from / 64; w < words_; ++w) {
      Word bits = want_free ? free_[r * words_ + w] : ~free_[r * words_ + w];
      if (w == from / 64) bits &= kAll << (from % 64);
      if (bits != 0) return std::min(nx_, 64 * w + static_cast<std::size_t>(std::countr_zero(bits)));
    }
    return nx_;
  }

  // Each free run of row r with a reached voxel is reached whole and seeds its neighbours' rows.
  void spread_row(std::size_t r) {
    const std::size_t y = r % ny_, z = r / ny_;
    std::size_t x = 0;
    while (x < nx_) {
      const std::size_t a = next(r, x, true);
      if (a >= nx_) break;
      const std::size_t b = next(r, a, false);
      x = b;
      bool hit = false, whole = true;
      for (std::size_t w = a / 64; w < words_ && 64 * w < b; ++w) {
        const Word run = range_word(w, a, b), got = reached_[r * words_ + w] & run;
        hit = hit || got != 0;
        whole = whole && got == run;
      }
      if (!hit) continue;
      if (!whole)
        for (std::size_t w = a / 64; w < words_ && 64 * w < b; ++w)
          reached_[r * words_ + w] |= range_word(w, a, b);
      if (y > 0) seed(r - 1, a, b);
      if (y + 1 < ny_) seed(r + 1, a, b);
      if (z > 0) seed(r - ny_, a, b);
      if (z + 1 < nz_) seed(r + ny_, a, b);
    }
  }

  openvdb::Coord lo_;
  std::size_t nx_, ny_, nz_;
  std::size_t words_;  // per row
  std::size_t rows_;
  std::vector<Word> free_, reached_;
  std::vector<char> queued_;
  std::vector<std::size_t> stack_;
};

}  // namespace

void fill_closed_voids(openvdb::FloatGrid& fill, const openvdb::CoordBBox& box, bool open_bottom,
                       double solid_fill) {
  RowFlood flood(box);
  flood.mark_free(fill, box, solid_fill);
  flood.seed_open_sides(open_bottom);
  flood.flood();
  flood.fill_unreached(fill);
}

}  // namespace beadtwin::sim
