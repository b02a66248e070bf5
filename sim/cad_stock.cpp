#include "sim/cad_stock.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <Eigen/Geometry>

#include "core/error.hpp"
#include "core/percentile.hpp"
#include "sim/print_surface.hpp"
#include "sim/triangle_sampling.hpp"
#include "sim/trilinear.hpp"

namespace beadtwin::sim {
namespace {

using Vec3 = Eigen::Vector3d;

// A face is on the plate when its outward normal is within about 25° of straight down (cos 25° ≈ 0.9)...
constexpr double kDownNormalZ = -0.9;
// ...and it lies within this many voxels above the bottom of the lowest printed voxel.
constexpr double kPlateVoxels = 1.0;
// The least and the most stock are found to within this share of a voxel.
constexpr double kExtremeVoxels = 0.01;

// Whether `tri` faces down: its outward side (from the CAD's distance, since the winding may be either
// way) has a normal within about 25° of -z.
bool faces_down(const SampledTriangle& tri, const openvdb::FloatGrid& cad_distance, double voxel_mm) {
  Vec3 n = (tri.b - tri.a).cross(tri.c - tri.a).normalized();
  if (std::abs(n.z()) < -kDownNormalZ) return false;
  const Vec3 centre = (tri.a + tri.b + tri.c) / 3.0;
  const auto acc = cad_distance.getConstUnsafeAccessor();
  const double ahead = trilinear(acc, cad_distance.transform(), centre + 0.5 * voxel_mm * n);
  const double behind = trilinear(acc, cad_distance.transform(), centre - 0.5 * voxel_mm * n);
  if (ahead < behind) n = -n;  // the distance grows outward
  return n.z() <= kDownNormalZ;
}

// The stock at p: its distance to the print's surface, up to the band, positive inside the print and
// negative outside (NearestTriangles::distance), looked for no further than `reach` (then the band).
double stock_at(const Vec3& p, double reach, const NearestTriangles& print,
                const openvdb::FloatGrid::ConstUnsafeAccessor& solid,
                const openvdb::math::Transform& transform, double band_mm) {
  NearestTriangles::Distance d = print.distance(p, reach);
  if (!d.found && reach < band_mm) d = print.distance(p, band_mm);  // rounding's safety net
  // Beyond the band, far from any surface, the fill tells inside from outside.
  const bool inside = d.found ? !d.outside : trilinear(solid, transform, p) >= kPrintedFill;
  return inside ? d.mm : -d.mm;
}

// The samples of one triangle (for_each_cell), each weighted by the area it stands for, with its stock
// (stock_at). The nearest triangle is looked for no further than the last sample's distance and the step
// from it (the distance to a surface changes no faster than the point moves): the searches stay small.
void sample_triangle(const SampledTriangle& tri, const NearestTriangles& print,
                     const openvdb::FloatGrid::ConstUnsafeAccessor& solid,
                     const openvdb::math::Transform& transform, const StockGeometry& g, double plate_top_mm,
                     std::vector<StockSample>& out) {
  std::size_t k = tri.first_sample;
  if (tri.on_plate && std::max({tri.a.z(), tri.b.z(), tri.c.z()}) <= plate_top_mm) {
    // Wholly on the plate: its samples count towards the plate's area only, and have no stock to measure.
    sample_points(tri.a, tri.b, tri.c, g.spacing_mm, [&](const Vec3&, double area) {
      StockSample& s = out[k++];
      s.area_mm2 = area;
      s.on_plate = true;
    });
    return;
  }
  Vec3 last(0, 0, 0);
  double reach = g.band_mm;  // from the last sample's distance; the band for the first
  for_each_cell(tri.a, tri.b, tri.c, g.spacing_mm, [&](const SampleCell& cell) {
    const Vec3& p = cell.point;
    if (k > tri.first_sample) reach = std::min(g.band_mm, (reach + (p - last).norm()) * (1.0 + 1e-9));
    StockSample& s = out[k++];
    s.stock_mm = stock_at(p, reach, print, solid, transform, g.band_mm);
    last = p;
    reach = std::abs(s.stock_mm);
    s.area_mm2 = cell.area;
    s.on_plate = tri.on_plate && p.z() <= plate_top_mm;
  });
}

// The area-weighted figures of the samples, reduced in sample order on one thread: the same sums for any
// number of threads. The extremes are the samples' (sharpened by the caller). The percentiles by selection
// (weighted_percentile), which is much faster than sorting millions of samples.
StockStats reduce(const std::vector<StockSample>& samples, double requested_stock_mm) {
  StockStats out;
  std::vector<Weighted> kept;
  kept.reserve(samples.size());
  double area = 0.0, sum = 0.0, under = 0.0, below = 0.0;
  double least = std::numeric_limits<double>::infinity(), most = -least;
  for (const StockSample& s : samples) {
    if (s.on_plate) {
      out.plate_area_mm2 += s.area_mm2;
      continue;
    }
    kept.push_back({s.stock_mm, s.area_mm2});
    area += s.area_mm2;
    sum += s.area_mm2 * s.stock_mm;
    least = std::min(least, s.stock_mm);
    most = std::max(most, s.stock_mm);
    if (s.stock_mm < 0) under += s.area_mm2;
    if (s.stock_mm < requested_stock_mm) below += s.area_mm2;
  }
  if (kept.empty())
    throw InputError({}, "cad",
                     "every face of the CAD lies on the build plate: there is no surface to measure");
  out.samples = kept.size();
  out.area_mm2 = area;
  out.least_mm = least;
  out.most_mm = most;
  out.mean_mm = sum / area;
  out.p05_mm = weighted_percentile(kept, area, 0.05);
  out.median_mm = weighted_percentile(kept, area, 0.50);
  out.p95_mm = weighted_percentile(kept, area, 0.95);
  out.undercut_fraction = under / area;
  out.below_requested_fraction = below / area;
  return out;
}

}  // namespace

std::vector<SampledTriangle> cad_triangles(const CadSurface& cad, double spacing_mm,
                                           std::size_t max_samples) {
  std::vector<SampledTriangle> out;
  out.reserve(cad.triangles.size());
  std::size_t samples = 0;
  for (const auto& t : cad.triangles) {
    SampledTriangle tri{cad.vertices[static_cast<std::size_t>(t[0])],
                        cad.vertices[static_cast<std::size_t>(t[1])],
                        cad.vertices[static_cast<std::size_t>(t[2])]};
    if ((tri.b - tri.a).cross(tri.c - tri.a).norm() <= 0) continue;  // degenerate: no area to sample
    tri.first_sample = samples;
    tri.samples = count_samples(tri.a, tri.b, tri.c, spacing_mm, max_samples - samples);
    samples += tri.samples;
    if (samples > max_samples)
      throw InputError(
          {}, "cad",
          fmt::format("sampling the CAD every {} mm takes more than {:.3g} samples: use a larger "
                      "spacing",
                      spacing_mm, static_cast<double>(max_samples)));
    out.push_back(tri);
  }
  return out;
}

void mark_plate(std::vector<SampledTriangle>& triangles, const openvdb::FloatGrid& cad_distance,
                double voxel_mm, double plate_z_mm) {
  for (SampledTriangle& t : triangles) {
    const double lowest = std::min({t.a.z(), t.b.z(), t.c.z()});
    t.on_plate = lowest <= plate_z_mm + kPlateVoxels * voxel_mm && faces_down(t, cad_distance, voxel_mm);
  }
}

StockStats measure_stock(const std::vector<SampledTriangle>& triangles, const NearestTriangles& print,
                         const openvdb::FloatGrid& solid, const StockGeometry& g, double requested_stock_mm,
                         double plate_z_mm) {
  const std::size_t total = triangles.empty() ? 0 : triangles.back().first_sample + triangles.back().samples;
  std::vector<StockSample> samples(total);
  const double plate_top = plate_z_mm + kPlateVoxels * g.voxel_mm;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, triangles.size()),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      const auto acc = solid.getConstUnsafeAccessor();
                      for (std::size_t i = range.begin(); i < range.end(); ++i)
                        sample_triangle(triangles[i], print, acc, solid.transform(), g, plate_top, samples);
                    });
  StockStats out = reduce(samples, requested_stock_mm);
  {
    const auto acc = solid.getConstUnsafeAccessor();
    ExtremeSearch search;
    search.spacing_mm = g.spacing_mm;
    search.band_mm = g.band_mm;
    search.tolerance_mm = kExtremeVoxels * g.voxel_mm;
    search.plate_top_mm = plate_top;
    const StockProbe probe = [&](const Vec3& p, double reach) {
      return stock_at(p, reach, print, acc, solid.transform(), g.band_mm);
    };
    sharpen_stock_extremes(triangles, samples, probe, search, out.least_mm, out.most_mm);
  }
  // No surface within the band: the truth is further out.
  out.least_clamped = out.least_mm <= -g.band_mm;
  out.most_clamped = out.most_mm >= g.band_mm;
  return out;
}

}  // namespace beadtwin::sim
