#include "sim/cad_compare.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "core/error.hpp"
#include "sim/cad_stock.hpp"
#include "sim/material_outside.hpp"
#include "sim/print_surface.hpp"
#include "sim/skin_deviation.hpp"

namespace beadtwin::sim {
namespace {

constexpr double kMaxBandVoxels = 256.0;  // half-width of a band, voxels
constexpr double kMaxBandVolume = 4e8;    // voxels the CAD's band may hold, both sides (about 3 GB at most)
constexpr double kMaxSamples = 5e7;       // samples on the CAD surface
constexpr double kMaxDenseVoxels = 4e9;   // the print's bounding box, a bit each, to find its closed voids
constexpr double kMaxVoxelIndex = 1e9;    // voxel indices are 32-bit: keep well inside them
constexpr double kMinSpacingVoxels = 1.0 / 16.0;

// The options' problems on voxels of `voxel_mm`, added to `add`.
template <class Add>
void check_options(double voxel_mm, const CadCompareOptions& o, const Add& add) {
  if (!(o.band_mm >= 2 * voxel_mm && o.band_mm <= kMaxBandVoxels * voxel_mm))
    add(fmt::format("band_mm must be 2 to {} voxels ({:.6g} to {:.6g} mm), got {}", kMaxBandVoxels,
                    2 * voxel_mm, kMaxBandVoxels * voxel_mm, o.band_mm));
  if (!std::isfinite(o.requested_stock_mm))
    add(fmt::format("requested_stock_mm must be finite, got {}", o.requested_stock_mm));
  if (!(o.sample_spacing_mm == 0 ||
        (o.sample_spacing_mm >= kMinSpacingVoxels * voxel_mm && std::isfinite(o.sample_spacing_mm))))
    add(fmt::format("sample_spacing_mm must be 0 (the voxel size) or at least 1/16 voxel ({:.6g} mm), got {}",
                    kMinSpacingVoxels * voxel_mm, o.sample_spacing_mm));
}

// The CAD's problems (no triangles, vertices not finite or out of the voxel index range, indices out of
// range) on voxels of `voxel_mm`, added to `add`.
template <class Add>
void check_cad(double voxel_mm, const CadSurface& cad, const Add& add) {
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
  if (extent / voxel_mm > kMaxVoxelIndex)
    add(fmt::format("the CAD reaches {:.6g} mm from the origin, beyond the voxel index range at {} mm voxels",
                    extent, voxel_mm));
  const auto n = static_cast<long long>(cad.vertices.size());
  for (std::size_t t = 0; t < cad.triangles.size(); ++t) {
    const auto& tri = cad.triangles[t];
    if (std::any_of(tri.begin(), tri.end(), [&](int i) { return i < 0 || i >= n; })) {
      add(fmt::format("CAD triangle {} names vertex {} {} {}, but there are {} vertices", t, tri[0], tri[1],
                      tri[2], n));
      break;
    }
  }
}

// Throws InputError when the CAD (checked) has no area, or its distance grid would not fit in memory.
void check_cad_budget(const CadSurface& cad, const StockGeometry& g) {
  double area = 0.0;
  for (const auto& tri : cad.triangles) {
    const Eigen::Vector3d& a = cad.vertices[static_cast<std::size_t>(tri[0])];
    const Eigen::Vector3d& b = cad.vertices[static_cast<std::size_t>(tri[1])];
    const Eigen::Vector3d& c = cad.vertices[static_cast<std::size_t>(tri[2])];
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

// The checks of the CAD and the options on voxels of `voxel_mm`, and the geometry they give.
StockGeometry validate_cad(double voxel_mm, const CadSurface& cad, const CadCompareOptions& o) {
  StockGeometry g;
  g.voxel_mm = voxel_mm;
  if (!(g.voxel_mm > 0 && std::isfinite(g.voxel_mm)))
    throw InputError({}, "voxel_size",
                     fmt::format("the deposit's voxel size must be positive, got {}", g.voxel_mm));
  g.band_mm = o.band_mm;
  g.spacing_mm = o.sample_spacing_mm > 0 ? o.sample_spacing_mm : g.voxel_mm;
  std::string problems;
  const auto add = [&](const std::string& problem) { problems += (problems.empty() ? "" : "; ") + problem; };
  check_options(g.voxel_mm, o, add);
  check_cad(g.voxel_mm, cad, add);
  if (!problems.empty()) throw InputError({}, "cad", problems);
  check_cad_budget(cad, g);  // now that every number is known good
  return g;
}

StockGeometry validate(const Deposit& deposit, const CadSurface& cad, const CadCompareOptions& o) {
  if (!deposit.fill || deposit.fill->activeVoxelCount() == 0)
    throw InputError("nothing was deposited: there is no printed part to compare with the CAD");
  const StockGeometry g = validate_cad(deposit.fill->voxelSize()[0], cad, o);
  const double box = static_cast<double>(deposit.fill->evalActiveVoxelBoundingBox().expandBy(1).volume());
  if (box > kMaxDenseVoxels)
    throw InputError(
        {}, "voxel_size",
        fmt::format("the print's bounding box holds {:.3g} voxels of {} mm, more than the comparison "
                    "with the CAD takes ({:.3g}); use a larger voxel size",
                    box, g.voxel_mm, kMaxDenseVoxels));
  return g;
}

void copy_stock(const StockStats& s, CadComparison& out) {
  out.min_stock_mm = s.least_mm;
  out.max_stock_mm = s.most_mm;
  out.mean_stock_mm = s.mean_mm;
  out.p05_stock_mm = s.p05_mm;
  out.median_stock_mm = s.median_mm;
  out.p95_stock_mm = s.p95_mm;
  out.min_stock_clamped = s.least_clamped;
  out.max_stock_clamped = s.most_clamped;
  out.undercut_fraction = s.undercut_fraction;
  out.below_requested_stock_fraction = s.below_requested_fraction;
  out.cad_area_mm2 = s.area_mm2;
  out.plate_area_mm2 = s.plate_area_mm2;
  out.cad_samples = s.samples;
}

void copy_deviation(const SkinDeviation& d, CadComparison& out) {
  out.deviation_mean_mm = d.mean_mm;
  out.deviation_rms_mm = d.rms_mm;
  out.deviation_min_mm = d.min_mm;
  out.deviation_max_mm = d.max_mm;
  out.deviation_min_clamped = d.min_clamped;
  out.deviation_max_clamped = d.max_clamped;
  out.skin_area_mm2 = d.area_mm2;
  out.skin_samples = d.samples;
}

}  // namespace

CadDistance cad_distance(const CadSurface& cad, double voxel_size_mm, const CadCompareOptions& options) {
  openvdb::initialize();
  const StockGeometry g = validate_cad(voxel_size_mm, cad, options);
  CadDistance out;
  out.voxel_mm = g.voxel_mm;
  out.band_mm = g.band_mm;
  out.field = std::make_shared<const CadField>(cad, *deposit_transform(g.voxel_mm), g.band_mm);
  return out;
}

CadComparison compare_with_cad(const Deposit& deposit, const CadSurface& cad,
                               const CadCompareOptions& options, const CadDistance* made_ahead) {
  openvdb::initialize();
  const StockGeometry g = validate(deposit, cad, options);
  std::vector<SampledTriangle> triangles =
      cad_triangles(cad, g.spacing_mm, static_cast<std::size_t>(kMaxSamples));
  CadComparison out;
  out.band_mm = g.band_mm;
  const int plate_k = plate_row(*deposit.fill);
  out.plate_z_mm = plate_k * g.voxel_mm;

  const bool ahead = made_ahead != nullptr && made_ahead->field && made_ahead->voxel_mm == g.voxel_mm &&
                     made_ahead->band_mm == g.band_mm &&
                     made_ahead->field->grid().transform() == deposit.fill->transform();
  const std::shared_ptr<const CadField> field =
      ahead ? made_ahead->field : std::make_shared<const CadField>(cad, deposit.fill->transform(), g.band_mm);
  if (options.exclude_plate) mark_plate(triangles, field->grid(), g.voxel_mm, out.plate_z_mm);
  // The extension's bottom is out of reach.
  const int depth = static_cast<int>(std::ceil(g.band_mm / g.voxel_mm)) + 2;
  const openvdb::FloatGrid::Ptr solid = solid_print(*deposit.fill, plate_k, options.exclude_plate, depth);
  const NearestTriangles print = print_surface(solid);
  copy_stock(measure_stock(triangles, print, *solid, g, options.requested_stock_mm, out.plate_z_mm), out);
  const double lowest_z = options.exclude_plate ? out.plate_z_mm : -std::numeric_limits<double>::infinity();
  copy_deviation(measure_skin_deviation(print, *field, g.voxel_mm, g.band_mm, lowest_z), out);
  const MaterialOutside outside = measure_material_outside(*deposit.fill, field->grid(), g.voxel_mm);
  out.outside_volume_mm3 = outside.volume_mm3;
  out.machining_waste_fraction = outside.fraction;
  out.cad_distance = field;
  return out;
}

}  // namespace beadtwin::sim
