#include "sim/cad_compare.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <openvdb/math/Operators.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <Eigen/Geometry>

#include "core/error.hpp"

namespace beadtwin::sim {
namespace {

constexpr double kPrintedFill = 0.5;  // the printed part: voxels at least half full (as the renderer draws)
// A face is on the plate when its outward normal is within about 25° of straight down (cos 25° ≈ 0.9)...
constexpr double kDownNormalZ = -0.9;
// ...and it lies within this many voxels above the bottom of the lowest printed voxel.
constexpr double kPlateVoxels = 1.0;
constexpr double kMaxBandVoxels = 256.0;  // half-width of a band, voxels
constexpr double kMaxBandVolume = 4e8;    // voxels the two bands may hold together (about 3 GB at most)
constexpr double kMaxSamples = 5e7;       // samples on the CAD surface
constexpr double kMaxDenseVoxels = 4e9;   // the print's bounding box, a bit each, to find its closed voids
constexpr double kMaxVoxelIndex = 1e9;    // voxel indices are 32-bit: keep well inside them
constexpr double kMinSpacingVoxels = 1.0 / 16.0;
// The print's distance grid inside it is built this deep first (voxels; see compare_with_cad).
constexpr double kPrintInsideFirstVoxels = 4.0;

using Vec3 = Eigen::Vector3d;

openvdb::Vec3d to_vdb(const Vec3& p) {
  return {p.x(), p.y(), p.z()};
}

// --- Inputs ---

struct Geometry {
  double voxel_mm = 0.0;
  double spacing_mm = 0.0;
  double band_mm = 0.0;
  double print_outside_mm = 0.0;  // the print's band outside it
};

// A triangle is sampled as the centroids of n² equal triangles of a uniform subdivision, n = ceil(longest
// edge / spacing) ("up" ones at barycentric ((i + 1/3)/n, (j + 1/3)/n), "down" ones at ((i + 2/3)/n,
// (j + 2/3)/n)), each of area A/n². A long thin triangle (its longest edge squared more than 8 times its
// area) is first cut in two across the midpoint of its longest edge, again and again until it is not thin
// or no longer than the spacing: n² slivers would put (length / spacing)² samples on it, most of a thin
// CAD's samples (17 million on the LSAM mould's 26,000 triangles), where its length needs length / spacing.
constexpr double kThin = 8.0;

// (a, b, c) turned so that its first two corners end its longest edge; whether it is thin (its longest edge
// squared more than kThin times its area) and longer than the spacing, and so to be halved.
struct Turned {
  Vec3 p, q, r;
  double longest_sq = 0.0, area = 0.0;
  bool halve = false;
};
Turned turn(const Vec3& a, const Vec3& b, const Vec3& c, double spacing) {
  const double ab = (b - a).squaredNorm(), bc = (c - b).squaredNorm(), ca = (a - c).squaredNorm();
  Turned t = ab >= bc && ab >= ca ? Turned{a, b, c} : bc >= ca ? Turned{b, c, a} : Turned{c, a, b};
  t.longest_sq = std::max({ab, bc, ca});
  t.area = 0.5 * (b - a).cross(c - a).norm();
  t.halve = t.longest_sq > kThin * t.area && t.longest_sq > spacing * spacing;
  return t;
}

// n for a triangle sampled whole: its longest edge over the spacing, rounded up.
double cuts(const Turned& t, double spacing) {
  return std::max(1.0, std::ceil(std::sqrt(t.longest_sq) / spacing));
}

// Calls `sample(point, area)` for every sample of (a, b, c), in a fixed order.
template <class Sample>
void sample_points(const Vec3& a, const Vec3& b, const Vec3& c, double spacing, Sample&& sample) {
  const Turned t = turn(a, b, c, spacing);
  if (t.halve) {
    const Vec3 m = 0.5 * (t.p + t.q);
    sample_points(t.p, m, t.r, spacing, sample);
    sample_points(m, t.q, t.r, spacing, sample);
    return;
  }
  const int n = static_cast<int>(cuts(t, spacing));
  const double piece = t.area / (static_cast<double>(n) * n);
  const auto put = [&](double u, double v) { sample(a + u * (b - a) + v * (c - a), piece); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      put((i + 1.0 / 3.0) / n, (j + 1.0 / 3.0) / n);
      if (i + j < n - 1) put((i + 2.0 / 3.0) / n, (j + 2.0 / 3.0) / n);
    }
}

// How many samples sample_points takes of (a, b, c), counting no further than `limit` (then more).
std::size_t count_samples(const Vec3& a, const Vec3& b, const Vec3& c, double spacing, std::size_t limit) {
  const Turned t = turn(a, b, c, spacing);
  if (!t.halve) {
    const double n = cuts(t, spacing);
    return n * n > static_cast<double>(limit) ? limit + 1 : static_cast<std::size_t>(n * n);
  }
  const Vec3 m = 0.5 * (t.p + t.q);
  const std::size_t first = count_samples(t.p, m, t.r, spacing, limit);
  if (first > limit) return first;
  return first + count_samples(m, t.q, t.r, spacing, limit - first);
}

// The checks of the CAD and the options on voxels of `voxel_mm`, and the geometry they give.
void validate_cad(double voxel_mm, const CadSurface& cad, const CadCompareOptions& o, Geometry& g) {
  std::string problems;
  const auto add = [&](const std::string& problem) { problems += (problems.empty() ? "" : "; ") + problem; };

  g.voxel_mm = voxel_mm;
  if (!(g.voxel_mm > 0 && std::isfinite(g.voxel_mm)))
    throw InputError({}, "voxel_size",
                     fmt::format("the deposit's voxel size must be positive, got {}", g.voxel_mm));
  g.band_mm = o.band_mm;
  g.print_outside_mm = std::min(o.band_mm, std::max(0.5 * o.band_mm, kPrintOutsideBandVoxels * g.voxel_mm));
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
  const double band_voxels = 2.0 * area / (g.voxel_mm * g.voxel_mm) * (2.0 * g.band_mm / g.voxel_mm);
  if (band_voxels > kMaxBandVolume)
    throw InputError(
        {}, "cad",
        fmt::format("the CAD's surface ({:.6g} mm²) is too large for {} mm voxels and a {} mm band: "
                    "its distance grids would hold about {:.3g} voxels (limit {:.3g})",
                    area, g.voxel_mm, g.band_mm, band_voxels, kMaxBandVolume));
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

// The lowest row of printed voxels (fill >= 0.5): the plate is at its bottom. Throws when none is printed.
int plate_row(const openvdb::FloatGrid& fill) {
  int lowest = std::numeric_limits<int>::max();
  for (auto it = fill.cbeginValueOn(); it; ++it)
    if (*it >= kPrintedFill) lowest = std::min(lowest, it.getCoord().z());
  if (lowest == std::numeric_limits<int>::max())
    throw InputError(
        fmt::format("nothing was deposited: no voxel of the deposit is at least {} full", kPrintedFill));
  return lowest;
}

// --- Distance grids ---

// The CAD's signed distance on the deposit's voxels. Points go to index space in double precision (the
// meshing's own world-space entry takes floats).
openvdb::FloatGrid::Ptr cad_distance_grid(const CadSurface& cad, const openvdb::math::Transform& transform,
                                          float band_voxels) {
  std::vector<openvdb::Vec3d> points;
  points.reserve(cad.vertices.size());
  for (const Vec3& v : cad.vertices) points.push_back(transform.worldToIndex(to_vdb(v)));
  std::vector<openvdb::Vec3I> triangles;
  triangles.reserve(cad.triangles.size());
  for (const auto& t : cad.triangles)
    triangles.emplace_back(static_cast<openvdb::Index32>(t[0]), static_cast<openvdb::Index32>(t[1]),
                           static_cast<openvdb::Index32>(t[2]));
  const openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3d, openvdb::Vec3I> mesh(points, triangles);
  auto grid = openvdb::tools::meshToVolume<openvdb::FloatGrid>(mesh, transform, band_voxels, band_voxels);
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  return grid;
}

// The print's signed distance: the fill fraction's isosurface at 0.5 — the surface the renderer draws —
// meshed (VolumeToMesh) and turned into a level set (meshToVolume), as tools::levelSetRebuild does, but with
// flat stretches of the surface merged into larger polygons (adaptivity 0.01: only where the normals agree
// within about 1 %): a bead's flank is a row of identical voxel faces along the bead, so this takes about a
// fifth of the polygons, and meshToVolume's time goes with the polygons. The distances are exact Euclidean
// distances to that surface; the alternative, fast sweeping from the fill grid (tools::fogToSdf), solves
// the eikonal equation to first order, with errors around corners that a stock measured a bead width deep
// would feel. Inside and outside come from the surface (meshToVolume ignores the winding), so the fill
// grid's convention (inside is above the isovalue, the opposite of a level set's) needs no negation.
openvdb::FloatGrid::Ptr print_distance_grid(const openvdb::FloatGrid& solid, float outside_voxels,
                                            float band_voxels) {
  constexpr double kAdaptivity = 0.01;
  openvdb::tools::VolumeToMesh mesher(kPrintedFill, kAdaptivity);
  mesher(solid);
  const openvdb::math::Transform& transform = solid.transform();
  std::vector<openvdb::Vec3s> points(mesher.pointListSize());
  for (std::size_t i = 0; i < points.size(); ++i)
    points[i] = openvdb::Vec3s(transform.worldToIndex(mesher.pointList()[i]));
  std::vector<openvdb::Vec4I> polygons;
  for (std::size_t n = 0; n < mesher.polygonPoolListSize(); ++n) {
    const openvdb::tools::PolygonPool& pool = mesher.polygonPoolList()[n];
    for (std::size_t i = 0; i < pool.numQuads(); ++i) polygons.push_back(pool.quad(i));
    for (std::size_t i = 0; i < pool.numTriangles(); ++i) {
      const openvdb::Vec3I& t = pool.triangle(i);
      polygons.emplace_back(t[0], t[1], t[2], openvdb::util::INVALID_IDX);
    }
  }
  const openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec4I> mesh(points, polygons);
  auto grid = openvdb::tools::meshToVolume<openvdb::FloatGrid>(mesh, transform, outside_voxels, band_voxels,
                                                               openvdb::tools::DISABLE_RENORMALIZATION);
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  return grid;
}

// Index of voxel (x, y, z) in a dense box `dim` voxels across.
std::size_t dense_index(const openvdb::Coord& dim, int x, int y, int z) {
  return (static_cast<std::size_t>(z) * static_cast<std::size_t>(dim.y()) + static_cast<std::size_t>(y)) *
             static_cast<std::size_t>(dim.x()) +
         static_cast<std::size_t>(x);
}

// Fills the voids the print closes in (fill fraction below 1/2, not connected to the outside through
// face-neighbouring voxels below 1/2): they are porosity, reported as such by the deposit, not surface, so
// their walls must not count as skin or bound a stock. `box` is the print's bounding box grown by a voxel on
// every side that opens to the outside; with the plate, its bottom is the plate row, which the table closes.
// A breadth-first flood from the box's open sides over a dense bit per voxel (set: solid, or reached from
// outside); the voxels left unset are the closed voids.
void fill_closed_voids(openvdb::FloatGrid& solid, const openvdb::CoordBBox& box, bool open_bottom) {
  const openvdb::Coord lo = box.min(), dim = box.dim();
  std::vector<std::uint64_t> done((static_cast<std::size_t>(box.volume()) + 63) / 64, 0);
  const auto is_done = [&](std::size_t i) { return (done[i / 64] >> (i % 64) & 1u) != 0; };
  const auto mark = [&](std::size_t i) { done[i / 64] |= std::uint64_t{1} << (i % 64); };
  for (auto it = solid.cbeginValueOn(); it; ++it)
    if (*it >= kPrintedFill && box.isInside(it.getCoord())) {
      const openvdb::Coord c = it.getCoord() - lo;
      mark(dense_index(dim, c.x(), c.y(), c.z()));
    }
  std::vector<std::size_t> frontier, next;
  const auto reach = [&](std::size_t i) {
    if (is_done(i)) return;
    mark(i);
    next.push_back(i);
  };
  for (int z = 0; z < dim.z(); ++z)
    for (int y = 0; y < dim.y(); ++y)
      for (int x = 0; x < dim.x(); ++x)
        if (x == 0 || y == 0 || x == dim.x() - 1 || y == dim.y() - 1 || z == dim.z() - 1 ||
            (open_bottom && z == 0))
          reach(dense_index(dim, x, y, z));
  const std::size_t sx = 1, sy = static_cast<std::size_t>(dim.x()),
                    sz = sy * static_cast<std::size_t>(dim.y());
  while (!next.empty()) {
    frontier.swap(next);
    next.clear();
    for (const std::size_t i : frontier) {
      const auto x = static_cast<int>(i % sy),
                 y = static_cast<int>((i / sy) % static_cast<std::size_t>(dim.y()));
      const auto z = static_cast<int>(i / sz);
      if (x > 0) reach(i - sx);
      if (x < dim.x() - 1) reach(i + sx);
      if (y > 0) reach(i - sy);
      if (y < dim.y() - 1) reach(i + sy);
      if (z > 0) reach(i - sz);
      if (z < dim.z() - 1) reach(i + sz);
    }
  }
  auto acc = solid.getAccessor();
  for (int z = 0; z < dim.z(); ++z)
    for (int y = 0; y < dim.y(); ++y)
      for (int x = 0; x < dim.x(); ++x)
        if (!is_done(dense_index(dim, x, y, z))) acc.setValue(lo.offsetBy(x, y, z), 1.0f);
}

// The print as its surface is measured: its closed voids filled and, with the plate, the table standing in
// for material — every voxel of its lowest printed row copied `depth` voxels down through the plate. The
// bottom the plate formed is then no surface, so it cannot limit the stock of the faces that meet it (a side
// face's stock would otherwise fall to nothing at its foot, however much material stands beside it); the
// sides carry straight on down, as the first row shaped them.
openvdb::FloatGrid::Ptr solid_print(const openvdb::FloatGrid& fill, int plate_k, bool on_plate, int depth) {
  auto solid = fill.deepCopy();
  openvdb::CoordBBox box = fill.evalActiveVoxelBoundingBox();
  box.expand(1);
  if (on_plate) box.min().z() = plate_k;
  fill_closed_voids(*solid, box, !on_plate);
  if (!on_plate) return solid;
  std::vector<std::pair<openvdb::Coord, float>> row;
  for (auto it = solid->cbeginValueOn(); it; ++it)
    if (it.getCoord().z() == plate_k) row.emplace_back(it.getCoord(), *it);
  auto acc = solid->getAccessor();
  for (const auto& [ijk, value] : row)
    for (int k = 1; k <= depth; ++k) acc.setValue(ijk.offsetBy(0, 0, -k), value);
  return solid;
}

template <class Accessor>
double sample(const Accessor& acc, const openvdb::math::Transform& transform, const Vec3& p) {
  return openvdb::tools::BoxSampler::sample(acc, transform.worldToIndex(to_vdb(p)));
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
  const double ahead = sample(acc, cad_distance.transform(), centre + 0.5 * voxel_mm * n);
  const double behind = sample(acc, cad_distance.transform(), centre - 0.5 * voxel_mm * n);
  if (ahead < behind) n = -n;  // the distance grows outward
  return n.z() <= kDownNormalZ;
}

struct Sample {
  double stock_mm = 0.0;
  double area_mm2 = 0.0;
  bool on_plate = false;
};

// The samples of one triangle (sample_points), each weighted by the area it stands for.
template <class Accessor>
void sample_triangle(const CadTriangle& tri, const Accessor& print, const openvdb::math::Transform& transform,
                     double spacing_mm, double plate_top_mm, std::vector<Sample>& out) {
  std::size_t k = tri.first_sample;
  sample_points(tri.a, tri.b, tri.c, spacing_mm, [&](const Vec3& p, double area) {
    Sample& s = out[k++];
    s.stock_mm = -sample(print, transform, p);
    s.area_mm2 = area;
    s.on_plate = tri.on_plate && p.z() <= plate_top_mm;
  });
}

// The area-weighted value below which `fraction` of the area lies, from samples sorted by value.
double percentile(const std::vector<const Sample*>& sorted, double total_area, double fraction) {
  double seen = 0.0;
  for (const Sample* s : sorted) {
    seen += s->area_mm2;
    if (seen >= fraction * total_area) return s->stock_mm;
  }
  return sorted.back()->stock_mm;
}

// Marks the triangles that may stand on the plate (faces down, within kPlateVoxels of it).
void mark_plate(std::vector<CadTriangle>& triangles, const openvdb::FloatGrid& cad_grid, const Geometry& g,
                double plate_z_mm) {
  for (CadTriangle& t : triangles) {
    const double lowest = std::min({t.a.z(), t.b.z(), t.c.z()});
    t.on_plate = lowest <= plate_z_mm + kPlateVoxels * g.voxel_mm && faces_down(t, cad_grid, g.voxel_mm);
  }
}

void measure_stock(const std::vector<CadTriangle>& triangles, const openvdb::FloatGrid& print,
                   const Geometry& g, const CadCompareOptions& o, CadComparison& out) {
  const std::size_t total = triangles.empty() ? 0 : triangles.back().first_sample + triangles.back().samples;
  std::vector<Sample> samples(total);
  const double plate_top = out.plate_z_mm + kPlateVoxels * g.voxel_mm;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, triangles.size()),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      const auto acc = print.getConstUnsafeAccessor();
                      for (std::size_t i = range.begin(); i < range.end(); ++i)
                        sample_triangle(triangles[i], acc, print.transform(), g.spacing_mm, plate_top,
                                        samples);
                    });

  // Reduced in sample order, on one thread: the same sums for any number of threads.
  std::vector<const Sample*> kept;
  kept.reserve(samples.size());
  double area = 0.0, sum = 0.0, under = 0.0, below = 0.0;
  for (const Sample& s : samples) {
    if (s.on_plate) {
      out.plate_area_mm2 += s.area_mm2;
      continue;
    }
    kept.push_back(&s);
    area += s.area_mm2;
    sum += s.area_mm2 * s.stock_mm;
    if (s.stock_mm < 0) under += s.area_mm2;
    if (s.stock_mm < o.requested_stock_mm) below += s.area_mm2;
  }
  if (kept.empty())
    throw InputError({}, "cad",
                     "every face of the CAD lies on the build plate: there is no surface to measure");
  // By stock, ties in sample order: the order a stable sort gives, on TBB's threads (7.8 million samples on
  // the LSAM mould took 1.3 s on one).
  tbb::parallel_sort(kept.begin(), kept.end(), [](const Sample* a, const Sample* b) {
    return a->stock_mm < b->stock_mm || (a->stock_mm == b->stock_mm && a < b);
  });
  out.cad_samples = kept.size();
  out.cad_area_mm2 = area;
  out.min_stock_mm = kept.front()->stock_mm;
  out.max_stock_mm = kept.back()->stock_mm;
  out.mean_stock_mm = sum / area;
  out.p05_stock_mm = percentile(kept, area, 0.05);
  out.median_stock_mm = percentile(kept, area, 0.50);
  out.p95_stock_mm = percentile(kept, area, 0.95);
  out.undercut_fraction = under / area;
  out.below_requested_stock_fraction = below / area;
  // Within a voxel of the band's edge the grid's values mix in the band's width: the truth is further out.
  const double edge = g.band_mm - g.voxel_mm;
  out.min_stock_clamped = out.min_stock_mm <= -(g.print_outside_mm - g.voxel_mm);
  out.max_stock_clamped = out.max_stock_mm >= edge;
}

// --- Deviation of the printed skin ---

struct SkinSums {
  double weight = 0.0, sum = 0.0, sum_sq = 0.0;
  double min = std::numeric_limits<double>::infinity(), max = -std::numeric_limits<double>::infinity();
  std::size_t count = 0;
};

// Points of the print's surface where it crosses the edges between voxel centres: a patch of area A with unit
// normal n crosses A·|n_a|/s² edges along axis a. Each crossing is kept on the axis its normal leans on most
// and weighted s²/|n_a|, so the weights add up to the surface's area — and a face that lies exactly halfway
// between two rows of voxel centres (every flat face of a layer) is counted once, never twice or not at all.
// Adds the CAD's distance at the crossings from voxel `ijk` (print distance `d0`) to `sums`.
template <class Accessor>
void add_crossings(const openvdb::Coord& ijk, double d0, const Accessor& print,
                   const openvdb::math::Transform& transform, const Accessor& cad,
                   const openvdb::math::Transform& cad_transform, double voxel_mm, double lowest_z_mm,
                   SkinSums& sums) {
  const auto gradient = [&](const openvdb::Coord& at) {
    const openvdb::Vec3f g = openvdb::math::ISGradient<openvdb::math::CD_2ND>::result(print, at);
    return Vec3(g.x(), g.y(), g.z());
  };
  for (int axis = 0; axis < 3; ++axis) {
    openvdb::Coord next = ijk;
    next[axis] += 1;
    const double d1 = print.getValue(next);
    if ((d0 < 0) == (d1 < 0)) continue;
    const Vec3 n = (gradient(ijk) + gradient(next)).normalized();
    if (!n.allFinite()) continue;
    int dominant = 0;
    n.cwiseAbs().maxCoeff(&dominant);
    if (dominant != axis) continue;
    openvdb::Vec3d x = transform.indexToWorld(ijk);
    x[axis] += d0 / (d0 - d1) * voxel_mm;
    const Vec3 p(x.x(), x.y(), x.z());
    if (p.z() < lowest_z_mm) continue;  // the table's stand-in below the plate, not print
    const double w = voxel_mm * voxel_mm / std::abs(n[axis]);
    const double deviation = sample(cad, cad_transform, p);
    sums.weight += w;
    sums.sum += w * deviation;
    sums.sum_sq += w * deviation * deviation;
    sums.min = std::min(sums.min, deviation);
    sums.max = std::max(sums.max, deviation);
    ++sums.count;
  }
}

void measure_skin(const openvdb::FloatGrid& print, const openvdb::FloatGrid& cad_grid, const Geometry& g,
                  const CadCompareOptions& o, CadComparison& out) {
  openvdb::tree::LeafManager<const openvdb::FloatTree> leaves(print.tree());
  std::vector<SkinSums> per_leaf(leaves.leafCount());
  const double lowest_z = o.exclude_plate ? out.plate_z_mm : -std::numeric_limits<double>::infinity();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.leafCount()),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      const auto pa = print.getConstUnsafeAccessor();
                      const auto ca = cad_grid.getConstUnsafeAccessor();
                      for (std::size_t l = range.begin(); l < range.end(); ++l)
                        for (auto it = leaves.leaf(l).cbeginValueOn(); it; ++it)
                          add_crossings(it.getCoord(), *it, pa, print.transform(), ca, cad_grid.transform(),
                                        g.voxel_mm, lowest_z, per_leaf[l]);
                    });
  SkinSums total;
  for (const SkinSums& s : per_leaf) {  // in leaf order: the same sums for any number of threads
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
  const double edge = g.band_mm - g.voxel_mm;
  out.deviation_min_clamped = out.deviation_min_mm <= -edge;
  out.deviation_max_clamped = out.deviation_max_mm >= edge;
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
  out.grid =
      cad_distance_grid(cad, *deposit_transform(g.voxel_mm), static_cast<float>(g.band_mm / g.voxel_mm));
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

  const auto band_voxels = static_cast<float>(g.band_mm / g.voxel_mm);
  const bool ahead = made_ahead != nullptr && made_ahead->grid && made_ahead->voxel_mm == g.voxel_mm &&
                     made_ahead->band_mm == g.band_mm &&
                     made_ahead->grid->transform() == deposit.fill->transform();
  const openvdb::FloatGrid::Ptr cad_grid =
      ahead ? made_ahead->grid : cad_distance_grid(cad, deposit.fill->transform(), band_voxels);
  if (options.exclude_plate) mark_plate(triangles, *cad_grid, g, out.plate_z_mm);
  const int depth = static_cast<int>(std::ceil(band_voxels)) + 2;  // the extension's bottom is out of reach
  const openvdb::FloatGrid::Ptr solid = solid_print(*deposit.fill, plate_k, options.exclude_plate, depth);
  const auto outside_voxels = static_cast<float>(g.print_outside_mm / g.voxel_mm);
  // The print's band inside it is built kPrintInsideFirstVoxels deep first, and again at the whole band
  // only when a stock reaches within a voxel of that depth: the grid's values inside the first depth are
  // the same either way, so the figures are too.
  const float inside_first = std::min(band_voxels, static_cast<float>(kPrintInsideFirstVoxels));
  openvdb::FloatGrid::Ptr print = print_distance_grid(*solid, outside_voxels, inside_first);
  CadComparison first = out;
  measure_stock(triangles, *print, g, options, first);
  if (inside_first < band_voxels && first.max_stock_mm >= (inside_first - 1.0) * g.voxel_mm) {
    print = print_distance_grid(*solid, outside_voxels, band_voxels);
    measure_stock(triangles, *print, g, options, out);
  } else {
    out = first;
  }
  measure_skin(*print, *cad_grid, g, options, out);
  measure_outside(*deposit.fill, *cad_grid, g, out);
  out.cad_distance = cad_grid;
  return out;
}

double cad_distance_at(const openvdb::FloatGrid& cad_distance, const Eigen::Vector3d& point_mm) {
  // An accessor of its own per call (unregistered: cheap to make): safe from any thread, and its cache
  // still serves the eight lookups of the trilinear sample.
  return sample(cad_distance.getConstUnsafeAccessor(), cad_distance.transform(), point_mm);
}

}  // namespace beadtwin::sim
