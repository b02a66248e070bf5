// The printed part against its CAD: a bar sliced with outer stock, deposited, and measured against a box
// cut from its middle.
//
// The geometry every expectation below comes from. The outline grown by the outer stock S is the stock
// envelope; the first boundary pass runs w/2 inside it, so its bead's outer edge lies on the envelope. The
// bead's section is a stadium (core/bead.hpp), so its edge reaches S beyond the CAD face only at the layer's
// mid-height, and S − h/2 at the layer's top and bottom, where its round side (radius h/2) meets the next
// layer's: between two layers the print's surface has a groove. Stock is the distance from a point of the
// CAD surface to the print's surface:
//  - with S >= h/2, a point level with a groove has the groove's floor straight out. The voxels cannot hold
//    the groove's sharp floor: the surface is where the fill fraction, averaged over each voxel and
//    interpolated between voxel centres, is 1/2, and the nearest voxel centres lie s/2 above and below the
//    floor, where the bead reaches (w − h)/2 + sqrt((h/2)² − (h/2 − s/2)²) = S − h/2 + sqrt(s (2h − s))/2
//    out (for w = 2S). That is the least stock on the sides.
//  - with S < h/2, a point level with a groove lies outside the print, nearest to the round sides (centre
//    h/2 − S in and h/2 up or down, radius h/2): stock h/2 − hypot(h/2 − S, h/2), which the voxels do not
//    blur (the round sides are smooth).
// The part printed is a bar, 40 mm longer than the box at each end: a pass's corners are where the deposit
// spreads a turning bead's material (each move keeps its own volume), and these tests are about the sides.
// The box's end faces lie inside the bar. The layers hold boundary passes only, two along each side of an
// envelope 74 mm wide (w + 3 · 0.9 w: passes 10 % overlapped meet in the middle), so no fill leaves a gap.
#include "sim/cad_compare.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include <tbb/global_control.h>

#include "core/error.hpp"
#include "sim/deposit.hpp"
#include "slicer/mesh.hpp"
#include "slicer/plan.hpp"

namespace beadtwin::sim {
namespace {

constexpr double kLength = 120.0, kHeight = 20.0;      // the box, mm
constexpr double kBarEnd = 40.0;                       // the bar runs this much further at each end
constexpr double kLayer = 5.0, kBead = 20.0;           // h and w, mm
constexpr double kVoxel = 1.0;                         // fine enough to see the grooves
constexpr double kEnvelope = kBead + 3 * 0.9 * kBead;  // two passes a side, 74 mm
constexpr double kBand = 20.0;                         // past every stock but the box's ends inside the bar

slicer::SectionParams bar_section(double outer_stock_mm, int stock_on_top) {
  slicer::SectionParams s;
  s.name = "bar";
  s.z_min_mm = 0;
  s.z_max_mm = kHeight;
  s.layer_height_mm = kLayer;
  s.bead_width_mm = kBead;
  s.print_speed_mm_s = 50;
  s.travel_speed_mm_s = 200;
  s.boundary.passes = 2;
  s.outer_stock_mm = outer_stock_mm;
  s.stock_on_top = stock_on_top;
  return s;
}

struct Printed {
  slicer::TriangleMesh cad;
  Deposit deposit;
};

// The box of `width` and the bar around it, printed with stock S: the envelope is width + 2 S.
Printed print_bar(double outer_stock_mm, int stock_on_top) {
  const double width = kEnvelope - 2 * outer_stock_mm;
  const slicer::TriangleMesh bar =
      slicer::make_box({kLength + 2 * kBarEnd, width, kHeight}, {-kBarEnd, 0, 0});
  const std::vector<slicer::SectionParams> sections = {bar_section(outer_stock_mm, stock_on_top)};
  Printed p;
  p.cad = slicer::make_box({kLength, width, kHeight});
  DepositOptions o;
  o.voxel_size_mm = kVoxel;
  p.deposit = deposit(slicer::plan_toolpath(bar, sections, MotionLimits{}), o);
  return p;
}

CadCompareOptions options(double requested_stock_mm) {
  CadCompareOptions o;
  o.band_mm = kBand;
  o.requested_stock_mm = requested_stock_mm;
  return o;
}

CadComparison compare(const Printed& p, const CadCompareOptions& o) {
  return compare_with_cad(p.deposit, {p.cad.vertices, p.cad.triangles}, o);
}

// The bar printed with S = w/2 (the first pass on the box's outline) and three layers of stock on top;
// printed once, and compared once with the stock it was asked for.
constexpr double kStock = 0.5 * kBead;
constexpr int kTopLayers = 3;
const Printed& stocked() {
  static const Printed p = print_bar(kStock, kTopLayers);
  return p;
}
const CadComparison& stocked_comparison() {
  static const CadComparison c = compare(stocked(), options(kStock));
  return c;
}

TEST(CadCompare, PrintWithStockLeavesTheGrooveDepthLessThanTheStock) {
  const CadComparison& c = stocked_comparison();
  const double r = 0.5 * kLayer;
  // The groove between two stacked beads' round sides: its floor lies h/2 inside the beads' widest, which
  // lie S out from the box. The deposit keeps the groove (the next bead does not sink into the notch
  // outside a wall's flank, docs/physics.md), but the voxels round its sharp floor off (above): the least
  // stock is S − h/2 + ½√(s(2h − s)) (9.0 mm), never less than the groove's true floor, S − h/2.
  const double groove_floor = kStock - r;  // 7.5 mm
  const double expected_min = groove_floor + 0.5 * std::sqrt(kVoxel * (2 * kLayer - kVoxel));
  EXPECT_NEAR(c.min_stock_mm, expected_min, 0.25 * kVoxel);
  EXPECT_GT(c.min_stock_mm, groove_floor);
  EXPECT_EQ(c.undercut_fraction, 0.0);
  EXPECT_FALSE(c.min_stock_clamped);
  // The box's ends lie deep inside the bar: more stock than the band measures, reported as at least that.
  EXPECT_TRUE(c.max_stock_clamped);
  EXPECT_GE(c.max_stock_mm, kBand - kVoxel);
  EXPECT_LE(c.min_stock_mm, c.p05_stock_mm);
  EXPECT_LE(c.p05_stock_mm, c.median_stock_mm);
  EXPECT_LE(c.median_stock_mm, c.p95_stock_mm);
  EXPECT_LE(c.p95_stock_mm, c.max_stock_mm);
  // The box's sides, ends and top; its bottom stands on the plate and is left out.
  const double width = kEnvelope - 2 * kStock, bottom = kLength * width;
  EXPECT_NEAR(c.cad_area_mm2, 2 * (kLength + width) * kHeight + bottom, 1e-6 * bottom);
  EXPECT_NEAR(c.plate_area_mm2, bottom, 1e-6 * bottom);
  EXPECT_EQ(c.plate_z_mm, 0.0);
  // The skin: the same surface sampled, so no nearer the box than the least stock (to the sampling), and
  // as far as the band at the bar's ends.
  EXPECT_NEAR(c.deviation_min_mm, expected_min, 0.25 * kVoxel);
  EXPECT_GE(c.deviation_max_mm, kBand - kVoxel);
  EXPECT_GT(c.deviation_mean_mm, expected_min);
  EXPECT_GE(c.deviation_rms_mm, c.deviation_mean_mm);
  EXPECT_GT(c.skin_area_mm2, c.cad_area_mm2);  // it wraps the box, and more
  // Machining takes off everything but what lies inside the box, which is at most the box's volume.
  const double deposited = stocked().deposit.deposited_volume_mm3;
  EXPECT_GE(c.outside_volume_mm3, deposited - kLength * width * kHeight);
  EXPECT_LT(c.outside_volume_mm3, deposited);
  EXPECT_NEAR(c.machining_waste_fraction, c.outside_volume_mm3 / deposited, 1e-3);
  ASSERT_TRUE(c.cad_distance);
  // The CAD's distance: the stock's distance out from a face, negative inside.
  EXPECT_NEAR(c.cad_distance->at({0.5 * kLength, -kStock, 0.5 * kHeight}), kStock, 0.05);
  EXPECT_NEAR(c.cad_distance->at({0.5 * kLength, 0.5 * width, kHeight - 2.0}), -2.0, 0.05);
}

TEST(CadCompare, RequestedStockIsMetOnlyMidLayer) {
  // Asked for S, the sides get it only at the beads' widest: below S everywhere else on the sides.
  const CadComparison& c = stocked_comparison();
  const double width = kEnvelope - 2 * kStock;
  const double sides = 2 * kLength * kHeight / c.cad_area_mm2;
  EXPECT_GT(c.below_requested_stock_fraction, 0.8 * sides);
  EXPECT_LT(c.below_requested_stock_fraction, (2 * (kLength + width) * kHeight) / c.cad_area_mm2);
  const CadComparison lenient = compare(stocked(), options(c.min_stock_mm - 0.01));
  EXPECT_EQ(lenient.below_requested_stock_fraction, 0.0);
}

TEST(CadCompare, TooLittleOuterStockIsUndercut) {
  // The outline shrunk by 5 mm instead of grown: every point of the sides lies outside the print.
  constexpr double kShort = -5.0;
  const Printed p = print_bar(kShort, 1);
  const CadComparison c = compare(p, options(0.0));
  const double r = 0.5 * kLayer;
  const double expected_min = r - std::hypot(r - kShort, r);  // -5.41 mm, level with a groove
  EXPECT_NEAR(c.min_stock_mm, expected_min, 0.25 * kVoxel);
  EXPECT_FALSE(c.min_stock_clamped);
  // Short of the print: the sides (2 L H) all over; the top (under its layer of stock) and the ends' side
  // edges at least |S| in from the edges (less a voxel's rounding), where even the beads' widest falls
  // short, and at most as far as a groove's reach, h/2 − S, and a voxel.
  const double width = kEnvelope - 2 * kShort;
  const double sides = 2 * kLength * kHeight;
  const double strips = 2 * kLength + 4 * kHeight;  // the top's two long edges, the ends' four side edges
  EXPECT_GE(c.undercut_fraction, (sides + strips * (-kShort - kVoxel)) / c.cad_area_mm2);
  EXPECT_LE(c.undercut_fraction, (sides + strips * (r - kShort + kVoxel)) / c.cad_area_mm2);
  EXPECT_NEAR(c.cad_area_mm2, 2 * (kLength + width) * kHeight + kLength * width, 1e-3);
  EXPECT_EQ(c.below_requested_stock_fraction, c.undercut_fraction);  // requested 0: the same question
  EXPECT_LT(c.deviation_min_mm, 0.0);
}

TEST(CadCompare, AnUndercutDeeperThanTheBandIsReportedAsAtLeastIt) {
  // The outline shrunk by 25 mm: the sides lie 25 mm and more outside the print, beyond the 20 mm band. The
  // least stock is the band's edge, flagged; the sign, and so the undercut, is still known everywhere.
  const Printed p = print_bar(-25.0, 1);
  const CadComparison c = compare(p, options(0.0));
  EXPECT_TRUE(c.min_stock_clamped);
  EXPECT_EQ(c.min_stock_mm, -kBand);
  EXPECT_GE(c.undercut_fraction, 2 * kLength * kHeight / c.cad_area_mm2);
  // Shrunk by 15 mm, the sides lie inside the band: measured, not flagged. The print's round sides lie
  // (h/2)(√2 − 1) nearer the box's faces level with a groove than at their widest (TooLittleOuterStock...).
  const CadComparison inside = compare(print_bar(-15.0, 1), options(0.0));
  EXPECT_FALSE(inside.min_stock_clamped);
  EXPECT_NEAR(inside.min_stock_mm, 0.5 * kLayer - std::hypot(0.5 * kLayer + 15.0, 0.5 * kLayer),
              0.25 * kVoxel);
}

TEST(CadCompare, BottomOnThePlateDoesNotCount) {
  // The box's bottom is flush with the print's (both on the table): counted, it brings the least stock down
  // to nothing (and the sides' too, at their foot, with the print's bottom no longer the table's).
  const CadComparison& excluded = stocked_comparison();
  CadCompareOptions o = options(kStock);
  o.exclude_plate = false;
  const CadComparison counted = compare(stocked(), o);
  EXPECT_GT(excluded.min_stock_mm, kStock - 0.5 * kLayer);
  EXPECT_NEAR(counted.min_stock_mm, 0.0, 0.5 * kVoxel);
  EXPECT_EQ(counted.plate_area_mm2, 0.0);
  EXPECT_NEAR(counted.cad_area_mm2, excluded.cad_area_mm2 + excluded.plate_area_mm2,
              1e-6 * counted.cad_area_mm2);
}

// A slab 40 x 40 x 20 mm of 1 mm voxels on the plate, whole.
Deposit whole_slab() {
  Deposit d;
  d.voxel_size_mm = 1.0;
  d.fill = openvdb::FloatGrid::create(0.0f);
  d.fill->setTransform(deposit_transform(1.0));
  auto acc = d.fill->getAccessor();
  for (int k = 0; k < 20; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 40; ++i) acc.setValue({i, j, k}, 1.0f);
  return d;
}

// A slab of material 40 × 40 × 20 mm on the plate (1 mm voxels, fill 1), cut through at 10 mm by a slit
// `slit_voxels` thin (fill 0.2, across the whole slab and so open on every side), against a box 8 mm in from
// its sides and 8 mm tall: the slit passes 2 mm above the box's top.
CadComparison slab_with_slit(int slit_voxels) {
  Deposit d = whole_slab();
  auto acc = d.fill->getAccessor();
  for (int k = 10; k < 10 + slit_voxels; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 40; ++i) acc.setValue({i, j, k}, 0.2f);
  const slicer::TriangleMesh box = slicer::make_box({24, 24, 8}, {8, 8, 0});
  CadCompareOptions o;
  o.band_mm = 16.0;
  return compare_with_cad(d, {box.vertices, box.triangles}, o);
}

TEST(CadCompare, ASlitOneVoxelThinIsPorosityNotSurface) {
  // One voxel thin: the slit is filled but for its mouth, a notch round the slab's sides (fill 0.2 beside
  // 1: its tip 0.875 mm in, its floor at 10.125 mm), so the least stock is the box's top edges' distance to
  // that notch: √(7.125² + 2.125²) = 7.4 mm to its sharp tip, which the surface's mesh rounds off, and less
  // than the 8 mm to the slab's sides.
  const CadComparison one = slab_with_slit(1);
  EXPECT_GT(one.min_stock_mm, std::hypot(7.125, 2.125) - 0.05);
  EXPECT_LT(one.min_stock_mm, 7.9);
  // Two voxels thin: surface. Its floor (fill 1 at z = 9.5 mm, 0.2 at 10.5 mm, 1/2 between: 10.125 mm)
  // lies 2.125 mm above the box's top.
  const CadComparison two = slab_with_slit(2);
  EXPECT_NEAR(two.min_stock_mm, 1.5 + 0.5 / 0.8, 0.01);
  EXPECT_EQ(two.undercut_fraction, 0.0);
}

// A slab 100 x 40 x 20 mm of 1 mm voxels with a pocket 12 x 4 x 3 voxels inside it (x 58 to 70: across
// the 64-voxel words the flood of fill_closed_voids works in), 3 mm above the top of the CAD's box; open to
// the slab's top through a chimney 2 voxels across, or closed.
CadComparison slab_with_pocket(bool pocket, bool open) {
  Deposit d;
  d.voxel_size_mm = 1.0;
  d.fill = openvdb::FloatGrid::create(0.0f);
  d.fill->setTransform(deposit_transform(1.0));
  auto acc = d.fill->getAccessor();
  const auto in = [](int v, int from, int to) { return v >= from && v < to; };
  for (int k = 0; k < 20; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 100; ++i) {
        const bool hollow = pocket && ((in(i, 58, 70) && in(j, 18, 22) && in(k, 11, 14)) ||
                                       (open && in(i, 62, 64) && in(j, 19, 21) && in(k, 14, 20)));
        acc.setValue({i, j, k}, hollow ? 0.0f : 1.0f);
      }
  const slicer::TriangleMesh box = slicer::make_box({84, 24, 8}, {8, 8, 0});
  CadCompareOptions o;
  o.band_mm = 16.0;
  return compare_with_cad(d, {box.vertices, box.triangles}, o);
}

TEST(CadCompare, AClosedPocketIsPorosityAnOpenOneIsSurface) {
  // Closed: filled, so the print is measured as the whole slab, to the last bit.
  const CadComparison whole = slab_with_pocket(false, false), closed = slab_with_pocket(true, false);
  EXPECT_EQ(closed.min_stock_mm, whole.min_stock_mm);
  EXPECT_EQ(closed.mean_stock_mm, whole.mean_stock_mm);
  EXPECT_EQ(closed.median_stock_mm, whole.median_stock_mm);
  EXPECT_GT(whole.min_stock_mm, 7.9);  // the slab's sides, 8 mm out from the box's
  // Open: the pocket's floor (z = 11 mm) is surface, 3 mm above the box's top (z = 8 mm).
  const CadComparison open = slab_with_pocket(true, true);
  EXPECT_NEAR(open.min_stock_mm, 3.0, 0.05);
}

// The box `size` at `origin` with every face cut into strips `strip_mm` wide along its longer side, each
// strip two right triangles: slivers, as a CAD exports a long flat face. (The faces' edges are cut where
// their strips end, so a face's corners lie on its neighbours' edges: closed, though not edge to edge.)
slicer::TriangleMesh striped_box(const Eigen::Vector3d& size, const Eigen::Vector3d& origin,
                                 double strip_mm) {
  slicer::TriangleMesh m;
  const auto face = [&](const Eigen::Vector3d& corner, const Eigen::Vector3d& along,
                        const Eigen::Vector3d& across) {
    const int strips = static_cast<int>(std::lround(across.norm() / strip_mm));
    for (int i = 0; i < strips; ++i) {
      const Eigen::Vector3d a = corner + across * (double(i) / strips),
                            b = corner + across * (double(i + 1) / strips);
      const int first = static_cast<int>(m.vertices.size());
      m.vertices.insert(m.vertices.end(), {a, a + along, b + along, b});
      m.triangles.push_back({first, first + 1, first + 2});
      m.triangles.push_back({first, first + 2, first + 3});
    }
  };
  const Eigen::Vector3d x(size.x(), 0, 0), y(0, size.y(), 0), z(0, 0, size.z()), o = origin;
  face(o, x, y);      // bottom
  face(o + z, x, y);  // top
  face(o, x, z);      // the four sides, each along its horizontal edge
  face(o + y, x, z);
  face(o, y, z);
  face(o + x, y, z);
  return m;
}

TEST(CadCompare, SliversAreSampledByTheirAreaNotTheirLength) {
  // The whole slab against a box 24 x 24 x 8 mm 8 mm in from its sides: stock 8 mm on the box's sides, and
  // min(8 + u, 8 + v, 12) on its top (u, v from its nearest edges, 12 the slab's top above it), whose
  // integral over a quarter of the top is 8 · 144 + ∫₀⁴ (12 − t)² dt = 1557.33 mm³. So the mean stock over
  // the 1344 mm² that count (the bottom is on the plate) is (4 · 192 · 8 + 4 · 1557.33) / 1344 = 9.2063 mm.
  const Deposit slab = whole_slab();
  CadCompareOptions o;
  o.band_mm = 16.0;
  const slicer::TriangleMesh fat_box = slicer::make_box({24, 24, 8}, {8, 8, 0});
  const slicer::TriangleMesh thin_box = striped_box({24, 24, 8}, {8, 8, 0}, 0.5);
  const CadComparison fat = compare_with_cad(slab, {fat_box.vertices, fat_box.triangles}, o);
  const CadComparison thin = compare_with_cad(slab, {thin_box.vertices, thin_box.triangles}, o);
  constexpr double kArea = 24 * 24 + 4 * 24 * 8,
                   kMean = (4 * 192 * 8 + 4 * (8 * 144 + (1728 - 512) / 3.0)) / kArea;
  for (const CadComparison* c : {&fat, &thin}) {
    EXPECT_NEAR(c->cad_area_mm2, kArea, 1e-9 * kArea);
    EXPECT_NEAR(c->mean_stock_mm, kMean, 0.01);
    EXPECT_NEAR(c->min_stock_mm, 8.0, 0.02);  // the print's surface meshed adaptively, true to 0.013 mm
    EXPECT_NEAR(c->max_stock_mm, 12.0, 0.05);
    EXPECT_EQ(c->undercut_fraction, 0.0);
  }
  // A sample stands for up to a voxel's face of surface (1 mm²; more samples where cells are cut by a
  // triangle's sides), and a sliver narrower than a voxel takes one a voxel of its length, not the square
  // of it: the box's 416 slivers 24 mm long (256 of them on the sides and top) take 25 each.
  EXPECT_LE(fat.cad_samples, static_cast<std::size_t>(1.5 * kArea));
  EXPECT_LE(thin.cad_samples, 256u * 25u);
}

TEST(CadCompare, TheLeastStockIsFoundBetweenTheSamples) {
  // The whole slab with a groove two voxels wide and one deep up its side at y = 16 to 18 mm (one voxel
  // wide it would be a slit, filled but for its mouth), against the box 8 mm in. The print's surface there
  // comes to a ridge at x = 1 mm, y = 17 mm (OpenVDB's meshing puts a point in each cell between voxel
  // centres; off the even voxels, its adaptive meshing moves that ridge to 0.875 mm): the least stock is
  // 7 mm, on the box's side straight across from the ridge, growing as √(49 + d²) a distance d along the
  // side away from it. Sampled every 10 mm, the box's side has no sample near that line: the samples' least
  // stock is 7.244 mm; refining the samples' cells finds the 7.
  Deposit slab = whole_slab();
  auto acc = slab.fill->getAccessor();
  for (int k = 0; k < 20; ++k)
    for (int j = 16; j < 18; ++j) acc.setValueOff({0, j, k}, 0.0f);
  CadCompareOptions o;
  o.band_mm = 16.0;
  o.sample_spacing_mm = 10.0;
  const slicer::TriangleMesh box = slicer::make_box({24, 24, 8}, {8, 8, 0});
  const CadComparison c = compare_with_cad(slab, {box.vertices, box.triangles}, o);
  EXPECT_NEAR(c.min_stock_mm, 7.0, 0.011);  // to within a hundredth of a voxel
  EXPECT_NEAR(c.max_stock_mm, 12.0, 0.05);
}

TEST(CadCompare, SameNumbersForAnyNumberOfThreads) {
  const Printed& p = stocked();
  CadComparison one, two;
  {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = compare(p, options(kStock));
  }
  {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = compare(p, options(kStock));
  }
  EXPECT_EQ(one.min_stock_mm, two.min_stock_mm);
  EXPECT_EQ(one.max_stock_mm, two.max_stock_mm);
  EXPECT_EQ(one.mean_stock_mm, two.mean_stock_mm);
  EXPECT_EQ(one.median_stock_mm, two.median_stock_mm);
  EXPECT_EQ(one.undercut_fraction, two.undercut_fraction);
  EXPECT_EQ(one.below_requested_stock_fraction, two.below_requested_stock_fraction);
  EXPECT_EQ(one.cad_samples, two.cad_samples);
  EXPECT_EQ(one.deviation_mean_mm, two.deviation_mean_mm);
  EXPECT_EQ(one.deviation_rms_mm, two.deviation_rms_mm);
  EXPECT_EQ(one.deviation_min_mm, two.deviation_min_mm);
  EXPECT_EQ(one.deviation_max_mm, two.deviation_max_mm);
  EXPECT_EQ(one.skin_samples, two.skin_samples);
  EXPECT_EQ(one.skin_area_mm2, two.skin_area_mm2);
  EXPECT_EQ(one.outside_volume_mm3, two.outside_volume_mm3);
}

// The CAD's distance made ahead of the deposit (the run makes it while the deposit runs) gives the same
// comparison; one made for other voxels or another band is not used, and the comparison is still right.
TEST(CadCompare, TheCadsDistanceMadeAheadGivesTheSameNumbers) {
  const Printed& p = stocked();
  const CadSurface cad{p.cad.vertices, p.cad.triangles};
  const CadComparison& plain = stocked_comparison();
  const CadDistance ahead = cad_distance(cad, kVoxel, options(kStock));
  EXPECT_EQ(ahead.voxel_mm, kVoxel);
  EXPECT_EQ(ahead.band_mm, kBand);
  ASSERT_TRUE(ahead.field);
  EXPECT_TRUE(ahead.field->grid().transform() == p.deposit.fill->transform());
  const CadComparison with = compare_with_cad(p.deposit, cad, options(kStock), &ahead);
  EXPECT_EQ(with.cad_distance, ahead.field);  // used, not made again
  EXPECT_EQ(with.min_stock_mm, plain.min_stock_mm);
  EXPECT_EQ(with.max_stock_mm, plain.max_stock_mm);
  EXPECT_EQ(with.mean_stock_mm, plain.mean_stock_mm);
  EXPECT_EQ(with.deviation_rms_mm, plain.deviation_rms_mm);
  EXPECT_EQ(with.outside_volume_mm3, plain.outside_volume_mm3);
  for (const CadDistance& other : {cad_distance(cad, 2.0 * kVoxel, options(kStock)), [&] {
                                     CadCompareOptions o = options(kStock);
                                     o.band_mm = 0.5 * kBand;
                                     return cad_distance(cad, kVoxel, o);
                                   }()}) {
    const CadComparison again = compare_with_cad(p.deposit, cad, options(kStock), &other);
    EXPECT_NE(again.cad_distance, other.field);
    EXPECT_EQ(again.mean_stock_mm, plain.mean_stock_mm);
    EXPECT_EQ(again.deviation_rms_mm, plain.deviation_rms_mm);
  }
  // Bad input is refused ahead as it is in the comparison.
  CadCompareOptions bad = options(kStock);
  bad.band_mm = 0;
  EXPECT_THROW((void)cad_distance(cad, kVoxel, bad), InputError);
  EXPECT_THROW((void)cad_distance(CadSurface{}, kVoxel, options(kStock)), InputError);
}

TEST(CadCompare, BadInputIsAnInputError) {
  const Printed& p = stocked();
  const CadSurface cad{p.cad.vertices, p.cad.triangles};
  const auto message = [](const auto& call) {
    try {
      call();
    } catch (const InputError& e) {
      return e.message();
    }
    return std::string("no InputError");
  };
  // No deposit, or nothing in it.
  EXPECT_NE(
      message([&] { (void)compare_with_cad(Deposit{}, cad, options(0)); }).find("nothing was deposited"),
      std::string::npos);
  Deposit empty = p.deposit;
  empty.fill = openvdb::FloatGrid::create(0.0f);
  empty.fill->setTransform(deposit_transform(kVoxel));
  EXPECT_NE(message([&] { (void)compare_with_cad(empty, cad, options(0)); }).find("nothing was deposited"),
            std::string::npos);
  Deposit faint = p.deposit;
  faint.fill = openvdb::FloatGrid::create(0.0f);
  faint.fill->setTransform(deposit_transform(kVoxel));
  faint.fill->tree().setValue(openvdb::Coord(0, 0, 0), 0.25f);
  EXPECT_NE(message([&] { (void)compare_with_cad(faint, cad, options(0)); }).find("at least 0.5 full"),
            std::string::npos);
  // No triangles.
  EXPECT_NE(
      message([&] { (void)compare_with_cad(p.deposit, CadSurface{}, options(0)); }).find("no triangles"),
      std::string::npos);
  // A vertex that is not finite, and a triangle naming a vertex that is not there: both reported at once.
  std::vector<Eigen::Vector3d> vertices = p.cad.vertices;
  vertices[3].x() = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::array<int, 3>> triangles = p.cad.triangles;
  triangles[5][1] = 99;
  const std::string both = message([&] {
    (void)compare_with_cad(p.deposit, {vertices, triangles}, options(0));
  });
  EXPECT_NE(both.find("not finite (the first is vertex 3)"), std::string::npos) << both;
  EXPECT_NE(both.find("triangle 5 names vertex"), std::string::npos) << both;
  // Triangles that enclose nothing.
  const std::vector<Eigen::Vector3d> line = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  const std::vector<std::array<int, 3>> flat = {{0, 1, 2}};
  EXPECT_NE(message([&] {
              (void)compare_with_cad(p.deposit, {line, flat}, options(0));
            }).find("no area"),
            std::string::npos);
  // Options out of range.
  CadCompareOptions o = options(0);
  o.band_mm = 0;
  EXPECT_NE(message([&] { (void)compare_with_cad(p.deposit, cad, o); }).find("band_mm"), std::string::npos);
  o = options(std::numeric_limits<double>::infinity());
  EXPECT_NE(message([&] { (void)compare_with_cad(p.deposit, cad, o); }).find("requested_stock_mm"),
            std::string::npos);
  o = options(0);
  o.sample_spacing_mm = -1;
  EXPECT_NE(message([&] { (void)compare_with_cad(p.deposit, cad, o); }).find("sample_spacing_mm"),
            std::string::npos);
  // A CAD a thousand times too large (metres read as millimetres): refused before any grid is built.
  std::vector<Eigen::Vector3d> huge = p.cad.vertices;
  for (auto& v : huge) v *= 1000.0;
  EXPECT_NE(message([&] {
              (void)compare_with_cad(p.deposit, {huge, p.cad.triangles}, options(0));
            }).find("too large"),
            std::string::npos);
}

}  // namespace
}  // namespace beadtwin::sim
