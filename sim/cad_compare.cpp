#include "sim/cad_compare.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <Eigen/Geometry>

#include "core/error.hpp"
#include "core/percentile.hpp"
#include "sim/nearest_triangles.hpp"
#include "sim/print_surface.hpp"
#include "sim/triangle_sampling.hpp"
#include "sim/trilinear.hpp"

namespace beadtwin::sim {
namespace {

// A face is on the plate when its outward normal is within about 25° of straight down (cos 25° ≈ 0.9)...
constexpr double kDownNormalZ = -0.9;
// ...and it lies within this many voxels above the bottom of the lowest printed voxel.
constexpr double kPlateVoxels = 1.0;
constexpr double kMaxBandVoxels = 256.0;  // half-width of a band, voxels
constexpr double kMaxBandVolume = 4e8;    // voxels the CAD's band may hold, both sides (about 3 GB at most)
constexpr double kMaxSamples = 5e7;       // samples on the CAD surface
constexpr double kMaxDenseVoxels = 4e9;   // the print's bounding box, a bit each, to find its closed voids
constexpr double kMaxVoxelIndex = 1e9;    // voxel indices are 32-bit: keep well inside them
constexpr double kMinSpacingVoxels = 1.0 / 16.0;

using Vec3 = Eigen::Vector3d;

// --- Inputs ---

struct Geometry {
  double voxel_mm = 0.0;
  double spacing_mm = 0.0;
  double band_mm = 0.0;
};

// The checks of the CAD and the options on voxels of `voxel_mm`, and the geometry they give.
void validate_cad(double voxel_mm, const CadSurface& cad, const CadCompareOptions& o, Geometry& g) {
  std::string problems;
  const auto add = [&](const std::string& problem) { problems += (problems.empty() ? "" : "; ") + problem; };

  g.voxel_mm = voxel_mm;
  if (!(g.voxel_mm > 0 && std::isfinite(g.voxel_mm)))
    throw InputError({}, "voxel_size",
                     fmt::format("the deposit's voxel size must be positive, got {}", g.voxel_mm));
  g.band_mm = o.band_mm;
  g.spacing_mm = o.sample_spacing_mm > 0 ? o.sample_spacing_mm : g.voxel_mm;
  if (!(o.band_mm >= 2 * g.voxel_mm && o.band_mm <= kMaxBandVoxels * g.voxel_mm))
    add(fmt::format("band_mm must be 2 to {} voxels ({:.6g} to {:.6g} mm), got {}", kMaxBandVoxels,
                    2 * g.voxel_mm, kMaxBandVoxels * g.voxel_mm, o.band_mm));
  if (!std::isfinite(o.requested_stock_mm))
    add(fmt::format("requested_stock_mm must be finite, got {}", o.requested_stock_mm));
  if (!(o.sample_spacing_mm == 0 ||
        (o.sample_spacing_mm >= kMinSpacingVoxels * g.voxel_mm && std::isfinite(o.sample_spacing_mm))))
    add(fmt::format("sample_spacing_mm must be 0 (the voxel size) or at least 1/16 voxel ({:.6g} mm), got {}",
                    kMinSpacingVoxels * g.voxel_mm, o.sample_spacing_mm));

  if (cad.triangles.empty()) add("the CAD has no triangles");
  std::size_t bad_vertices = 0, first_bad = 0;
  double extent = 0.0;
  for (std::size_t i = 0; i < cad.vertices.size(); ++i) {
    if (!cad.vertices[i].allFinite()) {
      if (bad_vertices++ == 0) first_bad = i;
      continue;
    }
    extent = std::max(extent, cad.vertices[i].cwiseAbs().maxCoeff());
  }
  if (bad_vertices > 0)
    add(fmt::format("the CAD has {} vertices that are not finite (the first is vertex {})", bad_vertices,
                    first_bad));
  if (extent / g.voxel_mm > kMaxVoxelIndex)
    add(fmt::format("the CAD reaches {:.6g} mm from the origin, beyond the voxel index range at {} mm voxels",
                    extent, g.voxel_mm));
  const auto n = static_cast<long long>(cad.vertices.size());
  for (std::size_t t = 0; t < cad.triangles.size(); ++t) {
    const auto& tri = cad.triangles[t];
    if (std::any_of(tri.begin(), tri.end(), [&](int i) { return i < 0 || i >= n; })) {
      add(fmt::format("CAD triangle {} names vertex {} {} {}, but there are {} vertices", t, tri[0], tri[1],
                      tri[2], n));
      break;
    }
  }
  if (!problems.empty()) throw InputError({}, "cad", problems);

  // Budget, now that every number is known good.
  double area = 0.0;
  for (const auto& tri : cad.triangles) {
    const Vec3& a = cad.vertices[static_cast<std::size_t>(tri[0])];
    const Vec3& b = cad.vertices[static_cast<std::size_t>(tri[1])];
    const Vec3& c = cad.vertices[static_cast<std::size_t>(tri[2])];
    area += 0.5 * (b - a).cross(c - a).norm();
  }
  if (!(area > 0))
    throw InputError({}, "cad", "the CAD's triangles have no area: there is no surface to measure");
  const double band_voxels =
      area / (g.voxel_mm * g.voxel_mm) * (2.0 * CadField::narrow_voxels(g.band_mm, g.voxel_mm));
  if (band_voxels > kMaxBandVolume)
    throw InputError(
        {}, "cad",
        fmt::format("the CAD's surface ({:.6g} mm²) is too large for {} mm voxels: its distance grid "
                    "would hold about {:.3g} voxels (limit {:.3g})",
                    area, g.voxel_mm, band_voxels, kMaxBandVolume));
}

void validate(const Deposit& deposit, const CadSurface& cad, const CadCompareOptions& o, Geometry& g) {
  if (!deposit.fill || deposit.fill->activeVoxelCount() == 0)
    throw InputError("nothing was deposited: there is no printed part to compare with the CAD");
  validate_cad(deposit.fill->voxelSize()[0], cad, o, g);
  const double box = static_cast<double>(deposit.fill->evalActiveVoxelBoundingBox().expandBy(1).volume());
  if (box > kMaxDenseVoxels)
    throw InputError(
        {}, "voxel_size",
        fmt::format("the print's bounding box holds {:.3g} voxels of {} mm, more than the comparison "
                    "with the CAD takes ({:.3g}); use a larger voxel size",
                    box, g.voxel_mm, kMaxDenseVoxels));
}

// --- Stock over the CAD surface ---

struct CadTriangle {
  Vec3 a, b, c;
  std::size_t first_sample = 0;
  std::size_t samples = 1;  // sample_points' samples of it
  bool on_plate = false;    // faces down and may touch the plate: its samples near the plate are left out
};

// The CAD's triangles with area, each with its samples' place in the list of all samples. Throws InputError
// when they would take more than kMaxSamples samples.
std::vector<CadTriangle> cad_triangles(const CadSurface& cad, double spacing_mm) {
  const auto limit = static_cast<std::size_t>(kMaxSamples);
  std::vector<CadTriangle> out;
  out.reserve(cad.triangles.size());
  std::size_t samples = 0;
  for (const auto& t : cad.triangles) {
    CadTriangle tri{cad.vertices[static_cast<std::size_t>(t[0])],
                    cad.vertices[static_cast<std::size_t>(t[1])],
                    cad.vertices[static_cast<std::size_t>(t[2])]};
    if ((tri.b - tri.a).cross(tri.c - tri.a).norm() <= 0) continue;  // degenerate: no area to sample
    tri.first_sample = samples;
    tri.samples = count_samples(tri.a, tri.b, tri.c, spacing_mm, limit - samples);
    samples += tri.samples;
    if (samples > limit)
      throw InputError(
          {}, "cad",
          fmt::format("sampling the CAD every {} mm takes more than {:.3g} samples: use a larger "
                      "spacing",
                      spacing_mm, kMaxSamples));
    out.push_back(tri);
  }
  return out;
}

// Whether `tri` faces down: its outward side (from the CAD's distance, since the winding may be either
// way) has a normal within about 25° of -z.
bool faces_down(const CadTriangle& tri, const openvdb::FloatGrid& cad_distance, double voxel_mm) {
  Vec3 n = (tri.b - tri.a).cross(tri.c - tri.a).normalized();
  if (std::abs(n.z()) < -kDownNormalZ) return false;
  const Vec3 centre = (tri.a + tri.b + tri.c) / 3.0;
  const auto acc = cad_distance.getConstUnsafeAccessor();
  const double ahead = trilinear(acc, cad_distance.transform(), centre + 0.5 * voxel_mm * n);
  const double behind = trilinear(acc, cad_distance.transform(), centre - 0.5 * voxel_mm * n);
  if (ahead < behind) n = -n;  // the distance grows outward
  return n.z() <= kDownNormalZ;
}

struct Sample {
  double stock_mm = 0.0;
  double area_mm2 = 0.0;
  bool on_plate = false;
};

// The stock at p: its distance to the print's surface, up to the band, positive inside the print and
// negative outside (NearestTriangles::distance), looked for no further than `reach` (then the band).
template <class Accessor>
double stock_at(const Vec3& p, double reach, const NearestTriangles& print, const Accessor& solid,
                const openvdb::math::Transform& transform, const Geometry& g) {
  NearestTriangles::Distance d = print.distance(p, reach);
  if (!d.found && reach < g.band_mm) d = print.distance(p, g.band_mm);  // rounding's safety net
  // Beyond the band, far from any surface, the fill tells inside from outside.
  const bool inside = d.found ? !d.outside : trilinear(solid, transform, p) >= kPrintedFill;
  return inside ? d.mm : -d.mm;
}

// The samples of one triangle (for_each_cell), each weighted by the area it stands for, with its stock
// (stock_at). The nearest triangle is looked for no further than the last sample's distance and the step
// from it (the distance to a surface changes no faster than the point moves): the searches stay small.
template <class Accessor>
void sample_triangle(const CadTriangle& tri, const NearestTriangles& print, const Accessor& solid,
                     const openvdb::math::Transform& transform, const Geometry& g, double plate_top_mm,
                     std::vector<Sample>& out) {
  std::size_t k = tri.first_sample;
  if (tri.on_plate && std::max({tri.a.z(), tri.b.z(), tri.c.z()}) <= plate_top_mm) {
    // Wholly on the plate: its samples count towards the plate's area only, and have no stock to measure.
    sample_points(tri.a, tri.b, tri.c, g.spacing_mm, [&](const Vec3&, double area) {
      Sample& s = out[k++];
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
    Sample& s = out[k++];
    s.stock_mm = stock_at(p, reach, print, solid, transform, g);
    last = p;
    reach = std::abs(s.stock_mm);
    s.area_mm2 = cell.area;
    s.on_plate = tri.on_plate && p.z() <= plate_top_mm;
  });
}

// The least and the most stock over the CAD's surface (off the plate), to within kExtremeVoxels of a voxel:
// the samples' extremes sharpened by branch and bound. The stock changes no faster than the point moves
// (a distance), so no point of a cell has less stock than its sample's less the cell's radius: a cell whose
// bound is below the least found so far (or, for the most, above it) is cut into cells a quarter of its
// radius across and measured again, the least sample first, until no bound is beyond the extreme found by
// more than the tolerance. On the LSAM mould 804 and 335 of its 1.3 million cells are opened, 10,700 and
// 34,800 points measured (on one thread, 0.05 s): its least stock is −7.49 mm, where its samples' least
// was −7.07 mm (and that of the 7.2 million samples taken before the cells, −7.22 mm); its most 5.19 mm
// against 5.11 mm. The default scenario's least −5.35 mm against −4.64 mm, at a corner of the CAD.
constexpr double kExtremeVoxels = 0.01;
// Measurements the refinement of one extreme may take: beyond them (a flat extreme over a large area, the
// bound closing slowly) the deepest value found is kept, which the samples' is never beyond.
constexpr std::size_t kMaxRefinements = 50'000;

template <class Accessor>
void sharpen_extremes(const std::vector<CadTriangle>& triangles, const std::vector<Sample>& samples,
                      const NearestTriangles& print, const Accessor& solid,
                      const openvdb::math::Transform& transform, const Geometry& g, double plate_top_mm,
                      double& least, double& most) {
  const double tolerance = kExtremeVoxels * g.voxel_mm;
  for (const int sign : {1, -1}) {  // the least stock (of stock), then the most (the least of −stock)
    double best = sign > 0 ? least : -most;
    struct Open {
      double bound;  // no point of the cell has less (sign · stock)
      double value;  // sign · stock at its sample
      SampleCell cell;
      bool plate;  // of a triangle that may stand on the plate
    };
    // The cell with the most extreme sample first (its bound breaks ties): the extreme is found early,
    // and with it every cell whose bound does not pass it is dropped unopened. (The lowest bound first
    // opened the widest cells first, however ordinary their samples.)
    const auto later = [](const Open& x, const Open& y) {
      return x.value != y.value ? x.value > y.value : x.bound > y.bound;
    };
    std::priority_queue<Open, std::vector<Open>, decltype(later)> open(later);
    // No point of a cell is beyond its sample by more than its radius, nor beyond the band.
    const auto bound = [&](double value, double radius) { return std::max(value - radius, -g.band_mm); };
    // The samples whose cells may hide a more extreme stock, their cells regenerated triangle by triangle:
    // only the triangles with a sample that could, were its cell as wide as any (its sides are no longer
    // than the spacing, so no corner is further than √2 spacings from its sample).
    const double widest = std::sqrt(2.0) * g.spacing_mm * (1.0 + 1e-9);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
      const CadTriangle& tri = triangles[t];
      bool any = false;
      for (std::size_t k = tri.first_sample; k < tri.first_sample + tri.samples && !any; ++k)
        any = !samples[k].on_plate && bound(sign * samples[k].stock_mm, widest) < best - tolerance;
      if (!any) continue;
      std::size_t k = tri.first_sample;
      for_each_cell(tri.a, tri.b, tri.c, g.spacing_mm, [&](const SampleCell& cell) {
        const Sample& s = samples[k++];
        const double b = bound(sign * s.stock_mm, cell.radius);
        if (!s.on_plate && b < best - tolerance) open.push({b, sign * s.stock_mm, cell, tri.on_plate});
      });
    }
    std::size_t measured = 0;
    while (!open.empty() && measured < kMaxRefinements) {
      const Open o = open.top();
      open.pop();
      if (o.bound >= best - tolerance) continue;  // nothing beyond the extreme found so far
      const double spacing = 0.25 * o.cell.radius;
      // The cell's polygon as a fan of triangles from its first corner, each sampled at the finer spacing.
      for (std::size_t c = 1; c + 1 < o.cell.corners; ++c)
        for_each_cell(
            o.cell.corner[0], o.cell.corner[c], o.cell.corner[c + 1], spacing, [&](const SampleCell& part) {
              if (part.area <= 0 || (o.plate && part.point.z() <= plate_top_mm)) return;
              const double reach = std::min(
                  g.band_mm, (std::abs(o.value) + (part.point - o.cell.point).norm()) * (1.0 + 1e-9));
              const double value = sign * stock_at(part.point, reach, print, solid, transform, g);
              ++measured;
              best = std::min(best, value);
              const double b = bound(value, part.radius);
              if (b < best - tolerance) open.push({b, value, part, o.plate});
            });
    }
    (sign > 0 ? least : most) = sign * best;
  }
}

// Marks the triangles that may stand on the plate (faces down, within kPlateVoxels of it).
void mark_plate(std::vector<CadTriangle>& triangles, const openvdb::FloatGrid& cad_grid, const Geometry& g,
                double plate_z_mm) {
  for (CadTriangle& t : triangles) {
    const double lowest = std::min({t.a.z(), t.b.z(), t.c.z()});
    t.on_plate = lowest <= plate_z_mm + kPlateVoxels * g.voxel_mm && faces_down(t, cad_grid, g.voxel_mm);
  }
}

void measure_stock(const std::vector<CadTriangle>& triangles, const NearestTriangles& print,
                   const openvdb::FloatGrid& solid, const Geometry& g, const CadCompareOptions& o,
                   CadComparison& out) {
  const std::size_t total = triangles.empty() ? 0 : triangles.back().first_sample + triangles.back().samples;
  std::vector<Sample> samples(total);
  const double plate_top = out.plate_z_mm + kPlateVoxels * g.voxel_mm;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, triangles.size()),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      const auto acc = solid.getConstUnsafeAccessor();
                      for (std::size_t i = range.begin(); i < range.end(); ++i)
                        sample_triangle(triangles[i], print, acc, solid.transform(), g, plate_top, samples);
                    });

  // Reduced in sample order, on one thread: the same sums for any number of threads.
  // The percentiles by selection (weighted_percentile): sorting the LSAM mould's 7.2 million samples took
  // 1.6 s of a core.
  std::vector<Weighted> kept;
  kept.reserve(samples.size());
  double area = 0.0, sum = 0.0, under = 0.0, below = 0.0;
  double least = std::numeric_limits<double>::infinity(), most = -least;
  for (const Sample& s : samples) {
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
    if (s.stock_mm < o.requested_stock_mm) below += s.area_mm2;
  }
  if (kept.empty())
    throw InputError({}, "cad",
                     "every face of the CAD lies on the build plate: there is no surface to measure");
  {
    const auto acc = solid.getConstUnsafeAccessor();
    sharpen_extremes(triangles, samples, print, acc, solid.transform(), g, plate_top, least, most);
  }
  samples = {};
  out.cad_samples = kept.size();
  out.cad_area_mm2 = area;
  out.min_stock_mm = least;
  out.max_stock_mm = most;
  out.mean_stock_mm = sum / area;
  out.p05_stock_mm = weighted_percentile(kept, area, 0.05);
  out.median_stock_mm = weighted_percentile(kept, area, 0.50);
  out.p95_stock_mm = weighted_percentile(kept, area, 0.95);
  out.undercut_fraction = under / area;
  out.below_requested_stock_fraction = below / area;
  // No surface within the band: the truth is further out.
  out.min_stock_clamped = out.min_stock_mm <= -g.band_mm;
  out.max_stock_clamped = out.max_stock_mm >= g.band_mm;
}

// --- Deviation of the printed skin ---

struct SkinSums {
  double weight = 0.0, sum = 0.0, sum_sq = 0.0;
  double min = std::numeric_limits<double>::infinity(), max = -std::numeric_limits<double>::infinity();
  std::size_t count = 0;
};

// The print's surface sampled as the CAD's is (sample_points, at the voxel spacing), each sample weighted by
// the area it stands for. In fixed blocks of triangles, added up in block order: the same sums for any
// number of threads.
void measure_skin(const NearestTriangles& print, const CadField& cad, const Geometry& g,
                  const CadCompareOptions& o, CadComparison& out) {
  constexpr std::size_t kBlock = 4096;
  std::vector<SkinSums> per_block((print.triangles() + kBlock - 1) / kBlock);
  const double lowest_z = o.exclude_plate ? out.plate_z_mm : -std::numeric_limits<double>::infinity();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, per_block.size()),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      const auto ca = cad.grid().getConstUnsafeAccessor();
                      for (std::size_t b = range.begin(); b < range.end(); ++b) {
                        SkinSums& sums = per_block[b];
                        for (std::size_t i = b * kBlock; i < std::min(print.triangles(), (b + 1) * kBlock);
                             ++i) {
                          const std::array<Vec3, 3> t = print.triangle(i);
                          sample_points(t[0], t[1], t[2], g.voxel_mm, [&](const Vec3& p, double area) {
                            if (p.z() < lowest_z) return;  // the table's stand-in below the plate, not print
                            const double deviation = cad.at(ca, p);
                            sums.weight += area;
                            sums.sum += area * deviation;
                            sums.sum_sq += area * deviation * deviation;
                            sums.min = std::min(sums.min, deviation);
                            sums.max = std::max(sums.max, deviation);
                            ++sums.count;
                          });
                        }
                      }
                    });
  SkinSums total;
  for (const SkinSums& s : per_block) {
    total.weight += s.weight;
    total.sum += s.sum;
    total.sum_sq += s.sum_sq;
    total.min = std::min(total.min, s.min);
    total.max = std::max(total.max, s.max);
    total.count += s.count;
  }
  out.skin_samples = total.count;
  out.skin_area_mm2 = total.weight;
  if (total.count == 0) return;
  out.deviation_mean_mm = total.sum / total.weight;
  out.deviation_rms_mm = std::sqrt(total.sum_sq / total.weight);
  out.deviation_min_mm = total.min;
  out.deviation_max_mm = total.max;
  out.deviation_min_clamped = out.deviation_min_mm <= -g.band_mm;
  out.deviation_max_clamped = out.deviation_max_mm >= g.band_mm;
}

// --- Material outside the CAD ---

// Each voxel's material times the share of the voxel outside the CAD, 1/2 + d/s clamped to 0..1 (exact for
// a plane parallel to a voxel face through the voxel, and unbiased for any plane on average).
void measure_outside(const openvdb::FloatGrid& fill, const openvdb::FloatGrid& cad_grid, const Geometry& g,
                     CadComparison& out) {
  openvdb::tree::LeafManager<const openvdb::FloatTree> leaves(fill.tree());
  std::vector<std::array<double, 2>> per_leaf(leaves.leafCount(), {0.0, 0.0});  // material, outside
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.leafCount()),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      const auto ca = cad_grid.getConstUnsafeAccessor();
                      for (std::size_t l = range.begin(); l < range.end(); ++l)
                        for (auto it = leaves.leaf(l).cbeginValueOn(); it; ++it) {
                          const double share =
                              std::clamp(0.5 + ca.getValue(it.getCoord()) / g.voxel_mm, 0.0, 1.0);
                          per_leaf[l][0] += *it;
                          per_leaf[l][1] += *it * share;
                        }
                    });
  double material = 0.0, outside = 0.0;
  for (const auto& [m, o] : per_leaf) material += m, outside += o;
  const double voxel_volume = g.voxel_mm * g.voxel_mm * g.voxel_mm;
  out.outside_volume_mm3 = outside * voxel_volume;
  out.machining_waste_fraction = material > 0 ? outside / material : 0.0;
}

}  // namespace

CadDistance cad_distance(const CadSurface& cad, double voxel_size_mm, const CadCompareOptions& options) {
  openvdb::initialize();
  Geometry g;
  validate_cad(voxel_size_mm, cad, options, g);
  CadDistance out;
  out.voxel_mm = g.voxel_mm;
  out.band_mm = g.band_mm;
  out.field = std::make_shared<const CadField>(cad, *deposit_transform(g.voxel_mm), g.band_mm);
  return out;
}

CadComparison compare_with_cad(const Deposit& deposit, const CadSurface& cad,
                               const CadCompareOptions& options, const CadDistance* made_ahead) {
  openvdb::initialize();
  Geometry g;
  validate(deposit, cad, options, g);
  std::vector<CadTriangle> triangles = cad_triangles(cad, g.spacing_mm);
  CadComparison out;
  out.band_mm = g.band_mm;
  const int plate_k = plate_row(*deposit.fill);
  out.plate_z_mm = plate_k * g.voxel_mm;

  const bool ahead = made_ahead != nullptr && made_ahead->field && made_ahead->voxel_mm == g.voxel_mm &&
                     made_ahead->band_mm == g.band_mm &&
                     made_ahead->field->grid().transform() == deposit.fill->transform();
  const std::shared_ptr<const CadField> field =
      ahead ? made_ahead->field : std::make_shared<const CadField>(cad, deposit.fill->transform(), g.band_mm);
  if (options.exclude_plate) mark_plate(triangles, field->grid(), g, out.plate_z_mm);
  // The extension's bottom is out of reach.
  const int depth = static_cast<int>(std::ceil(g.band_mm / g.voxel_mm)) + 2;
  const openvdb::FloatGrid::Ptr solid = solid_print(*deposit.fill, plate_k, options.exclude_plate, depth);
  const NearestTriangles print = print_surface(solid);
  measure_stock(triangles, print, *solid, g, options, out);
  measure_skin(print, *field, g, options, out);
  measure_outside(*deposit.fill, field->grid(), g, out);
  out.cad_distance = field;
  return out;
}

}  // namespace beadtwin::sim
