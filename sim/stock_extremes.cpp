#include "sim/stock_extremes.hpp"

#include <algorithm>
#include <cmath>
#include <queue>
#include <vector>

#include "sim/triangle_sampling.hpp"

namespace beadtwin::sim {
namespace {

// A cell that may hide a more extreme stock than found so far, in the units of the search (sign · stock:
// the least of it is the extreme looked for).
struct OpenCell {
  double bound;  // no point of the cell has less
  double value;  // at its sample
  SampleCell cell;
  bool plate;  // of a triangle that may stand on the plate
};

// The cell with the most extreme sample first; the lower bound breaks ties.
struct Later {
  bool operator()(const OpenCell& x, const OpenCell& y) const {
    return x.value != y.value ? x.value > y.value : x.bound > y.bound;
  }
};
using OpenCells = std::priority_queue<OpenCell, std::vector<OpenCell>, Later>;

// The search for the least of sign · stock.
class Search {
 public:
  Search(const StockProbe& stock, const ExtremeSearch& s, int sign, double best)
      : stock_(stock), s_(s), sign_(sign), best_(best) {}

  // No point of a cell is beyond its sample by more than its radius, nor beyond the band.
  double bound(double value, double radius) const { return std::max(value - radius, -s_.band_mm); }
  bool may_pass(double bound) const { return bound < best_ - s_.tolerance_mm; }

  // Opens the cells of the samples that may hide a more extreme stock, regenerated triangle by triangle:
  // only the triangles with a sample that could, were its cell as wide as any (its sides are no longer than
  // the spacing, so no corner is further than √2 spacings from its sample).
  void open_samples(std::span<const SampledTriangle> triangles, std::span<const StockSample> samples) {
    const double widest = std::sqrt(2.0) * s_.spacing_mm * (1.0 + 1e-9);
    for (const SampledTriangle& tri : triangles) {
      bool any = false;
      for (std::size_t k = tri.first_sample; k < tri.first_sample + tri.samples && !any; ++k)
        any = !samples[k].on_plate && may_pass(bound(sign_ * samples[k].stock_mm, widest));
      if (!any) continue;
      std::size_t k = tri.first_sample;
      for_each_cell(tri.a, tri.b, tri.c, s_.spacing_mm, [&](const SampleCell& cell) {
        const StockSample& sample = samples[k++];
        const double b = bound(sign_ * sample.stock_mm, cell.radius);
        if (!sample.on_plate && may_pass(b)) open_.push({b, sign_ * sample.stock_mm, cell, tri.on_plate});
      });
    }
  }

  // Refines the open cells until none may pass the extreme found, or the measurements run out; returns the
  // extreme.
  double refine() {
    std::size_t measured = 0;
    while (!open_.empty() && measured < s_.max_measurements) {
      const OpenCell o = open_.top();
      open_.pop();
      if (!may_pass(o.bound)) continue;  // nothing beyond the extreme found so far
      const double spacing = 0.25 * o.cell.radius;
      // The cell's polygon as a fan of triangles from its first corner, each sampled at the finer spacing.
      for (std::size_t c = 1; c + 1 < o.cell.corners; ++c)
        for_each_cell(
            o.cell.corner[0], o.cell.corner[c], o.cell.corner[c + 1], spacing, [&](const SampleCell& part) {
              if (part.area <= 0 || (o.plate && part.point.z() <= s_.plate_top_mm)) return;
              const double reach = std::min(
                  s_.band_mm, (std::abs(o.value) + (part.point - o.cell.point).norm()) * (1.0 + 1e-9));
              const double value = sign_ * stock_(part.point, reach);
              ++measured;
              best_ = std::min(best_, value);
              const double b = bound(value, part.radius);
              if (may_pass(b)) open_.push({b, value, part, o.plate});
            });
    }
    return best_;
  }

 private:
  const StockProbe& stock_;
  const ExtremeSearch& s_;
  int sign_;
  double best_;
  OpenCells open_;
};

}  // namespace

void sharpen_stock_extremes(std::span<const SampledTriangle> triangles, std::span<const StockSample> samples,
                            const StockProbe& stock, const ExtremeSearch& search, double& least,
                            double& most) {
  for (const int sign : {1, -1}) {  // the least stock (of stock), then the most (the least of −stock)
    Search s(stock, search, sign, sign > 0 ? least : -most);
    s.open_samples(triangles, samples);
    (sign > 0 ? least : most) = sign * s.refine();
  }
}

}  // namespace beadtwin::sim
