// Tests of the stock over the CAD's surface (sim/cad_stock.hpp): which CAD faces stand on the plate, how the
// CAD is sampled, and the stock of a box inside a slab of voxels, worked out by hand.
#include "sim/cad_stock.hpp"

#include <algorithm>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "sim/deposit.hpp"
#include "sim/print_surface.hpp"
#include "sim/triangle_sampling.hpp"
#include "slicer/mesh.hpp"
#include "tests/sim/voxel_block.hpp"

namespace beadtwin::sim {
namespace {

// The box's triangles (in make_box's winding, or turned inside out), on voxels of 1 mm.
struct Cad {
  slicer::TriangleMesh mesh;
  CadSurface surface() const { return {mesh.vertices, mesh.triangles}; }
  explicit Cad(const Eigen::Vector3d& size, const Eigen::Vector3d& origin, bool inside_out = false)
      : mesh(slicer::make_box(size, origin)) {
    if (inside_out)
      for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  }
};

// The box's two bottom triangles stand on a plate at its bottom, whatever the winding; none do on a plate
// more than a voxel below it; the top faces never do.
TEST(CadStock, TheBottomFacesStandOnThePlate) {
  for (const bool inside_out : {false, true}) {
    const Cad cad({24, 24, 8}, {8, 8, 0}, inside_out);
    const openvdb::FloatGrid::Ptr distance = cad_distance_grid(cad.surface(), *deposit_transform(1.0), 2.0f);
    std::vector<SampledTriangle> triangles = cad_triangles(cad.surface(), 1.0, 1'000'000);
    ASSERT_EQ(triangles.size(), 12u);
    mark_plate(triangles, *distance, 1.0, 0.0);
    for (const SampledTriangle& t : triangles) {
      const bool bottom = std::max({t.a.z(), t.b.z(), t.c.z()}) == 0.0;
      EXPECT_EQ(t.on_plate, bottom) << inside_out;
    }
    mark_plate(triangles, *distance, 1.0, -1.5);
    for (const SampledTriangle& t : triangles) EXPECT_FALSE(t.on_plate);
  }
}

// Each triangle's samples follow the one before's; triangles without area are left out; more samples than
// the limit are refused.
TEST(CadStock, TheCadsSamplesAreListedTriangleByTriangle) {
  Cad cad({24, 24, 8}, {8, 8, 0});
  cad.mesh.triangles.push_back({0, 0, 1});  // no area
  const std::vector<SampledTriangle> triangles = cad_triangles(cad.surface(), 1.0, 1'000'000);
  ASSERT_EQ(triangles.size(), 12u);
  std::size_t next = 0;
  for (const SampledTriangle& t : triangles) {
    EXPECT_EQ(t.first_sample, next);
    EXPECT_EQ(t.samples, count_samples(t.a, t.b, t.c, 1.0, 1'000'000));
    next += t.samples;
  }
  EXPECT_THROW((void)cad_triangles(cad.surface(), 1.0, next - 1), InputError);
  EXPECT_EQ(cad_triangles(cad.surface(), 1.0, next).size(), 12u);
}

// A slab 40 x 40 x 20 mm of full 1 mm voxels on the plate, and a box 24 x 24 x 8 mm 8 mm in from its sides
// standing on the plate: stock 8 mm on the box's sides, min(8 + u, 8 + v, 12) on its top (u, v from its
// nearest edges; 12 the slab's top above it), the bottom on the plate. So the least is 8, the most 12, and
// the mean over the 1344 mm² that count (8 · 768 + 4 · 1557.33) / 1344 = 9.2063 mm (cad_compare_test.cpp
// works it out).
TEST(CadStock, TheStockOfABoxInsideASlab) {
  const openvdb::FloatGrid::Ptr solid = solid_print(*testing::full_block({40, 40, 20}), 0, true, 18);
  const NearestTriangles print = print_surface(solid);
  const Cad cad({24, 24, 8}, {8, 8, 0});
  StockGeometry g;
  g.voxel_mm = g.spacing_mm = 1.0;
  g.band_mm = 16.0;
  const openvdb::FloatGrid::Ptr distance = cad_distance_grid(cad.surface(), solid->transform(), 2.0f);
  std::vector<SampledTriangle> triangles = cad_triangles(cad.surface(), g.spacing_mm, 1'000'000);
  mark_plate(triangles, *distance, g.voxel_mm, 0.0);
  const StockStats s = measure_stock(triangles, print, *solid, g, 9.0, 0.0);
  constexpr double kArea = 24 * 24 + 4 * 24 * 8;
  EXPECT_NEAR(s.area_mm2, kArea, 1e-9 * kArea);
  EXPECT_NEAR(s.plate_area_mm2, 24 * 24, 1e-9 * kArea);
  EXPECT_NEAR(s.least_mm, 8.0, 0.02);
  EXPECT_NEAR(s.most_mm, 12.0, 0.05);
  EXPECT_NEAR(s.mean_mm, (4 * 192 * 8 + 4 * (8 * 144 + (1728 - 512) / 3.0)) / kArea, 0.01);
  EXPECT_LE(s.least_mm, s.p05_mm);
  EXPECT_LE(s.p05_mm, s.median_mm);
  EXPECT_LE(s.median_mm, s.p95_mm);
  EXPECT_LE(s.p95_mm, s.most_mm);
  EXPECT_EQ(s.undercut_fraction, 0.0);
  // Below 9 mm: the sides (768 mm²) and the top's rim within 1 mm of its edges (4 · 23 mm²), about.
  EXPECT_NEAR(s.below_requested_fraction, (768 + 4 * 23) / kArea, 0.02);
  EXPECT_FALSE(s.least_clamped);
  EXPECT_FALSE(s.most_clamped);
  EXPECT_GE(s.samples, static_cast<std::size_t>(kArea));
  // Every face on the plate: nothing to measure.
  std::vector<SampledTriangle> bottom;
  for (const SampledTriangle& t : triangles)
    if (t.on_plate) bottom.push_back(t);
  for (std::size_t i = 0, next = 0; i < bottom.size(); ++i) {
    bottom[i].first_sample = next;
    next += bottom[i].samples;
  }
  EXPECT_THROW((void)measure_stock(bottom, print, *solid, g, 9.0, 0.0), InputError);
}

}  // namespace
}  // namespace beadtwin::sim
