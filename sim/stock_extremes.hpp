// The least and the most stock over a sampled surface, found between the samples by branch and bound
// (docs/physics.md, the part against its CAD).
//
// The stock is a distance (to the print's surface), so it changes no faster than the point moves: no point
// of a sample's cell (sim/triangle_sampling.hpp) has less stock than the sample's less the cell's radius,
// nor more than the sample's plus it. A cell whose bound lies beyond the extreme found so far by more than
// the tolerance is cut into cells a quarter of its radius across and measured again, the cell with the most
// extreme sample first (its bound breaks ties): the extreme is found early, and with it every cell whose
// bound does not pass it is dropped unopened. The search ends when no open cell's bound is beyond the
// extreme found by more than the tolerance, or after a number of measurements (a flat extreme over a large
// area, where the bound closes slowly): then the deepest value found is kept, which the samples' is never
// beyond. On a large CAD a few hundred cells are opened.
#pragma once

#include <cstddef>
#include <functional>
#include <limits>
#include <span>

#include <Eigen/Core>

namespace beadtwin::sim {

// A triangle of the sampled surface (mm) and where its samples lie in the list of all samples: the
// for_each_cell samples of (a, b, c) at the spacing, in its order, from first_sample on.
struct SampledTriangle {
  Eigen::Vector3d a, b, c;
  std::size_t first_sample = 0;
  std::size_t samples = 1;
  bool on_plate = false;  // faces down and may touch the plate: its points at or below the plate are left out
};

// The stock at one sample and the area it stands for.
struct StockSample {
  double stock_mm = 0.0;
  double area_mm2 = 0.0;
  bool on_plate = false;  // left out
};

// The stock at `point_mm`, mm, for a point whose stock is known to be no further from zero than `reach_mm`
// (a hint: a probe may look no further for the nearest surface). It must change no faster than the point
// moves (1 mm per mm) and lie within ±band.
using StockProbe = std::function<double(const Eigen::Vector3d& point_mm, double reach_mm)>;

// How far the branch and bound searches.
struct ExtremeSearch {
  double spacing_mm = 0.0;    // the samples' spacing (> 0)
  double band_mm = 0.0;       // no stock lies beyond ±band_mm (> 0)
  double tolerance_mm = 0.0;  // how far beyond the extreme found a cell's bound may still lie (> 0)
  // Points of on_plate triangles at or below this height are left out.
  double plate_top_mm = -std::numeric_limits<double>::infinity();
  std::size_t max_measurements = 50'000;  // per extreme
};

// Sharpens `least` and `most` (on entry the extremes of the samples that are not on the plate; on return the
// least and the most stock over the surface to within the tolerance). `samples`: the stock at every sample
// of `triangles`, as `stock` gives it. Deterministic.
void sharpen_stock_extremes(std::span<const SampledTriangle> triangles, std::span<const StockSample> samples,
                            const StockProbe& stock, const ExtremeSearch& search, double& least,
                            double& most);

}  // namespace beadtwin::sim
