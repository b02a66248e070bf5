// Tests of pictures of a field (render_field): the value and depth it reports pixel by pixel, the cutaway's
// cut face, framing on a given box, and golden images compared with a tolerance.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>

#include "core/error.hpp"
#include "render/annotate.hpp"
#include "render/colormap.hpp"
#include "render/image.hpp"
#include "render/render.hpp"
#include "tests/render/box_deposit.hpp"

namespace beadtwin::render {
namespace {

using testing::make_box_deposit;

constexpr Rgb kMagenta{1.0f, 0.0f, 1.0f};

const sim::Deposit& box() {
  static const sim::Deposit deposit = make_box_deposit();
  return deposit;
}
const PreparedDeposit& prepared_box() {
  static const PreparedDeposit prepared(box());
  return prepared;
}

// The box's layer index as a float field on its material voxels.
const openvdb::FloatGrid& layer_field() {
  static const openvdb::FloatGrid::Ptr grid = [] {
    auto g = openvdb::FloatGrid::create(std::nanf(""));
    g->setTransform(box().layer->transform().copy());
    auto at = g->getAccessor();
    for (auto it = box().layer->cbeginValueOn(); it; ++it)
      if (*it >= 0) at.setValue(it.getCoord(), static_cast<float>(*it));
    return g;
  }();
  return *grid;
}

RenderOptions small(View view) {
  RenderOptions o;
  o.width = 240;
  o.height = 160;
  o.samples_per_pixel = 4;
  o.camera.view = view;
  o.background = o.background_bottom = kMagenta;
  o.ground_shadow = false;
  return o;
}

SurfaceField by_layer() {
  SurfaceField f;
  f.voxels = &layer_field();
  const ScalarScale scale{0.0, 11.0, ColourMap::viridis()};
  f.colour = [scale](double v) { return scale.colour(v); };
  return f;
}

// Every pixel on the part reports the layer of the material it shows, and how far it is; the rest NaN.
TEST(RenderField, ValuesAndDepthFollowThePart) {
  const FieldPicture p = render_field(prepared_box(), by_layer(), small(View::kFront));
  ASSERT_EQ(p.values.size(), 240u * 160u);
  std::size_t on = 0;
  float lowest = 1e9f, highest = -1e9f;
  for (std::size_t i = 0; i < p.values.size(); ++i) {
    const Rgb c = p.image.at(static_cast<int>(i % 240), static_cast<int>(i / 240));
    if (c == kMagenta) {
      EXPECT_TRUE(std::isnan(p.values[i])) << i;
      EXPECT_TRUE(std::isnan(p.depth[i])) << i;
      continue;
    }
    if (std::isnan(p.values[i])) continue;  // an edge pixel whose first samples missed
    ++on;
    EXPECT_EQ(p.values[i], std::round(p.values[i]));
    EXPECT_GT(p.depth[i], 0.0f);
    lowest = std::min(lowest, p.values[i]);
    highest = std::max(highest, p.values[i]);
  }
  EXPECT_GT(on, 2000u);
  EXPECT_EQ(lowest, 0.0f);
  EXPECT_EQ(highest, 11.0f);  // 60 mm of 5 mm layers
  // The front view is orthographic: the scale is the window's width over the image's.
  EXPECT_GT(p.mm_per_pixel, 0.0);
  EXPECT_LT(p.mm_per_pixel * 240, 400.0);
}

// A point function colours the part too, and the colour is the function's.
TEST(RenderField, PointFieldColoursThePart) {
  SurfaceField f;
  f.at_point = [](const Eigen::Vector3d& p) { return p.x() < 100.0 ? 0.0 : 1.0; };
  f.colour = [](double v) { return v < 0.5 ? Rgb{0.9f, 0.2f, 0.2f} : Rgb{0.2f, 0.3f, 0.9f}; };
  const FieldPicture p = render_field(prepared_box(), f, small(View::kFront));
  // Left half of the front face red, right half blue (hue, whatever the light).
  const Rgb left = p.image.at(70, 80), right = p.image.at(170, 80);
  EXPECT_GT(left.r, left.b);
  EXPECT_GT(right.b, right.r);
  EXPECT_EQ(p.values[80 * 240 + 70], 0.0f);
  EXPECT_EQ(p.values[80 * 240 + 170], 1.0f);
}

// Cut through the middle of the box's front wall (its bead runs along y = 0, 21 mm wide) and seen from the
// front: the cut face, at the plane, stands 10.5 mm behind the wall's outer face and shows the layers there.
// Cut behind the front wall instead (y = 30), the hollow inside shows the back wall's inner face (its bead
// along y = 200), 200 mm behind the front wall's outer face.
TEST(RenderField, CutawayShowsTheCutFace) {
  const FieldPicture whole = render_field(prepared_box(), by_layer(), small(View::kFront));
  RenderOptions o = small(View::kFront);
  o.cut = Cutaway{Eigen::Vector3f(0, 0, 0), -Eigen::Vector3f::UnitY()};
  const FieldPicture through = render_field(prepared_box(), by_layer(), o);
  o.cut = Cutaway{Eigen::Vector3f(0, 30, 0), -Eigen::Vector3f::UnitY()};
  const FieldPicture behind = render_field(prepared_box(), by_layer(), o);
  const std::size_t centre = 80 * 240 + 120;
  ASSERT_FALSE(std::isnan(whole.depth[centre]));
  ASSERT_FALSE(std::isnan(through.depth[centre]));
  ASSERT_FALSE(std::isnan(behind.depth[centre]));
  EXPECT_NEAR(through.depth[centre] - whole.depth[centre], 10.5f, 2.0f);
  EXPECT_EQ(through.values[centre], whole.values[centre]);                // the same layer, inside
  EXPECT_NEAR(behind.depth[centre] - whole.depth[centre], 200.0f, 3.0f);  // outer face -10.5, inner 189.5
  EXPECT_NE(through.image, whole.image);
  // Every pixel of the cut face at the centre row is nearer than the back wall: the face is solid (the
  // wall's beads overlap), with no hole to look through.
  for (int x = 100; x < 140; ++x) {
    const std::size_t i = 80 * 240 + static_cast<std::size_t>(x);
    EXPECT_LT(through.depth[i] - whole.depth[i], 15.0f) << x;
  }
}

TEST(RenderField, BadCutawayAndFieldAreCaught) {
  RenderOptions o = small(View::kFront);
  o.cut = Cutaway{Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()};
  EXPECT_THROW(render_field(prepared_box(), by_layer(), o), InputError);
  SurfaceField none;
  none.colour = [](double) { return Rgb{}; };
  EXPECT_THROW(render_field(prepared_box(), none, small(View::kFront)), InternalError);
}

// A frame box larger than the part (another variant's, say) makes the part smaller in the picture, in the
// same place for every picture that shares it.
TEST(RenderField, FramingOnAGivenBox) {
  RenderOptions o = small(View::kTop);
  const FieldPicture own = render_field(prepared_box(), by_layer(), o);
  o.frame = Eigen::AlignedBox3f(Eigen::Vector3f(-200, -200, 0), Eigen::Vector3f(400, 400, 60));
  const FieldPicture larger = render_field(prepared_box(), by_layer(), o);
  EXPECT_GT(larger.mm_per_pixel, 1.5 * own.mm_per_pixel);
}

// --- a picture traced once, coloured later ---

// The box's layer index on every voxel of its fill, as the pictures' fields are made (over the fill's
// voxels, NaN where a voxel has no layer); `shift` added, to tell two fields apart.
openvdb::FloatGrid::Ptr layer_on_fill(float shift) {
  auto g = openvdb::FloatGrid::create(std::nanf(""));
  g->setTransform(box().fill->transform().copy());
  // Accessors left unregistered with their trees: a tree destroyed after a registered accessor has come and
  // gone trips UndefinedBehaviorSanitizer inside TBB's hash map of accessors (a false finding).
  auto at = g->getUnsafeAccessor();
  auto layer = box().layer->getConstUnsafeAccessor();
  for (auto it = box().fill->cbeginValueOn(); it; ++it) {
    const int l = layer.getValue(it.getCoord());
    at.setValue(it.getCoord(), l >= 0 ? static_cast<float>(l) + shift : std::nanf(""));
  }
  return g;
}

SurfaceField field_of(const openvdb::FloatGrid& grid, ColourMap map) {
  SurfaceField f;
  f.voxels = &grid;
  const ScalarScale scale{0.0, 15.0, std::move(map)};
  f.colour = [scale](double v) { return scale.colour(v); };
  return f;
}

// The same values and depths, the same rays, and the same colours but for rounding.
void expect_same_picture(const FieldPicture& traced, const FieldPicture& direct) {
  ASSERT_EQ(traced.values.size(), direct.values.size());
  for (std::size_t i = 0; i < direct.values.size(); ++i) {
    ASSERT_EQ(std::bit_cast<std::uint32_t>(traced.values[i]), std::bit_cast<std::uint32_t>(direct.values[i]))
        << i;
    ASSERT_EQ(std::bit_cast<std::uint32_t>(traced.depth[i]), std::bit_cast<std::uint32_t>(direct.depth[i]))
        << i;
  }
  EXPECT_EQ(traced.stats.rays(), direct.stats.rays());
  EXPECT_EQ(traced.stats.rays_traced(), direct.stats.rays_traced());
  EXPECT_EQ(traced.mm_per_pixel, direct.mm_per_pixel);
  // Apart by float rounding: in an 8-bit file, hardly a pixel one step apart.
  std::size_t steps_apart = 0;
  const auto step = [](float c) { return std::lround(255.0f * c); };
  for (int y = 0; y < direct.image.height; ++y)
    for (int x = 0; x < direct.image.width; ++x) {
      const Rgb a = traced.image.at(x, y), b = direct.image.at(x, y);
      const float d = std::max({std::abs(a.r - b.r), std::abs(a.g - b.g), std::abs(a.b - b.b)});
      EXPECT_LE(d, 1e-4f) << x << ", " << y;
      steps_apart += step(a.r) != step(b.r) || step(a.g) != step(b.g) || step(a.b) != step(b.b);
    }
  EXPECT_LT(steps_apart, direct.values.size() / 1000);
}

// One trace coloured by two fields gives each the picture render_field draws of it: from a perspective
// view with the ground shadow, and cut away.
TEST(TracedPicture, ColoursEachFieldAsRenderFieldDrawsIt) {
  const openvdb::FloatGrid::Ptr layers = layer_on_fill(0.0f), shifted = layer_on_fill(4.0f);
  RenderOptions o = small(View::kIsometric);
  o.ground_shadow = true;
  o.background_bottom = Rgb{0.2f, 0.3f, 0.4f};
  for (const bool cut : {false, true}) {
    if (cut) o.cut = Cutaway{Eigen::Vector3f(100, 100, 0), -Eigen::Vector3f::UnitY()};
    const TracedPicture traced(prepared_box(), o);
    for (const auto* grid : {layers.get(), shifted.get()}) {
      const SurfaceField f =
          field_of(*grid, grid == layers.get() ? ColourMap::viridis() : ColourMap::inferno());
      ASSERT_TRUE(traced.colours(f));
      expect_same_picture(traced.colour(f), render_field(prepared_box(), f, o));
    }
  }
}

// A field on other voxels than the fill's or in another frame cannot be coloured on a trace: its values
// would come from other voxels than the trace found.
TEST(TracedPicture, TakesOnlyFieldsOnTheFillsVoxels) {
  const TracedPicture traced(prepared_box(), small(View::kFront));
  const openvdb::FloatGrid::Ptr moved = layer_on_fill(0.0f);
  moved->setTransform(openvdb::math::Transform::createLinearTransform(2.0 * box().fill->voxelSize()[0]));
  EXPECT_FALSE(traced.colours(field_of(*moved, ColourMap::viridis())));
  const openvdb::FloatGrid::Ptr fewer = layer_on_fill(0.0f);
  fewer->tree().setValueOff(box().fill->cbeginValueOn().getCoord());
  EXPECT_FALSE(traced.colours(field_of(*fewer, ColourMap::viridis())));
  EXPECT_TRUE(traced.colours(field_of(*layer_on_fill(0.0f), ColourMap::viridis())));
  EXPECT_GT(traced.memory_bytes(), 240u * 160u * 16u);
  RenderOptions bad = small(View::kFront);
  bad.samples_per_pixel = 0;
  EXPECT_THROW(TracedPicture(prepared_box(), bad), InputError);
}

// A field of points coloured on a trace: each pixel's value and depth as render_field gives them (the first
// sample's on the part), and its colour taken at the first sample on each voxel rather than smoothed over
// the samples: the same but along the line where the colour changes within a pixel.
TEST(TracedPicture, ColoursAFieldOfPointsAtTheFirstSampleOnEachVoxel) {
  SurfaceField f;  // the line inside a column of voxels
  f.at_point = [](const Eigen::Vector3d& p) { return p.x() < 101.7 ? 0.0 : 1.0; };
  f.colour = [](double v) { return v < 0.5 ? Rgb{0.9f, 0.2f, 0.2f} : Rgb{0.2f, 0.3f, 0.9f}; };
  const RenderOptions o = small(View::kFront);
  const TracedPicture traced(prepared_box(), o);
  ASSERT_TRUE(traced.colours(f));
  const FieldPicture a = traced.colour(f), b = render_field(prepared_box(), f, o);
  ASSERT_EQ(a.values.size(), b.values.size());
  for (std::size_t i = 0; i < a.values.size(); ++i) {
    ASSERT_EQ(std::bit_cast<std::uint32_t>(a.values[i]), std::bit_cast<std::uint32_t>(b.values[i])) << i;
    ASSERT_EQ(std::bit_cast<std::uint32_t>(a.depth[i]), std::bit_cast<std::uint32_t>(b.depth[i])) << i;
  }
  std::size_t apart = 0;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      const Rgb p = a.image.at(x, y), q = b.image.at(x, y);
      if (std::max({std::abs(p.r - q.r), std::abs(p.g - q.g), std::abs(p.b - q.b)}) < 1e-4f) continue;
      ++apart;
      EXPECT_LE(std::abs(x - 120), 2) << x << ", " << y;  // the box's front, 0..200 mm, is centred
    }
  EXPECT_GT(apart, 0u);  // some pixels on the line are smoothed in one and not the other
  EXPECT_LT(apart, 4u * static_cast<std::size_t>(o.height));
}

// --- golden images ---

// The largest share of pixels whose colour may differ from the reference by more than `kPixelTolerance`
// (any channel), and the mean difference allowed: rounding, another Embree build or CPU change edges a
// little, a real change (a colour, the light, the framing) moves far more.
constexpr float kPixelTolerance = 0.08f;
constexpr double kMaxDifferentShare = 0.01;
constexpr double kMaxMeanDifference = 0.01;

// Compares `image` with tests/render/golden/<name>.png; with BEADTWIN_UPDATE_GOLDEN=1 in the environment,
// writes it there instead (and the test passes): look at it before committing it.
void expect_matches_golden(const Image& image, const std::string& name) {
  const std::filesystem::path path =
      std::filesystem::path(BEADTWIN_SOURCE_DIR) / "tests" / "render" / "golden" / (name + ".png");
  if (const char* update = std::getenv("BEADTWIN_UPDATE_GOLDEN"); update && std::string(update) == "1") {
    std::filesystem::create_directories(path.parent_path());
    write_png(image, path);
    return;
  }
  ASSERT_TRUE(std::filesystem::exists(path)) << path << " is missing: run with BEADTWIN_UPDATE_GOLDEN=1";
  const Image golden = read_image(path);
  ASSERT_EQ(golden.width, image.width);
  ASSERT_EQ(golden.height, image.height);
  std::size_t different = 0;
  double sum = 0.0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const Rgb a = image.at(x, y), b = golden.at(x, y);
      const float d = std::max({std::abs(a.r - b.r), std::abs(a.g - b.g), std::abs(a.b - b.b)});
      sum += d;
      different += d > kPixelTolerance;
    }
  const double pixels = static_cast<double>(image.width) * image.height;
  EXPECT_LE(static_cast<double>(different) / pixels, kMaxDifferentShare) << name;
  EXPECT_LE(sum / pixels, kMaxMeanDifference) << name;
}

Annotation legend_for(const std::string& title) {
  Annotation a;
  a.title = title;
  a.subtitle = "box of 12 layers";
  Legend l;
  l.title = "layer";
  l.scale = ScalarScale{0.0, 11.0, ColourMap::viridis()};
  a.legend = l;
  return a;
}

TEST(RenderGolden, IsometricByLayerWithLegend) {
  RenderOptions o;
  o.width = 320;
  o.height = 200;
  const Annotation a = legend_for("Layers");
  const AnnotationLayout layout = layout_for(o.width, o.height, a);
  o.margins = {0.03, 0.03 + static_cast<double>(layout.legend_panel_px) / o.width,
               0.03 + static_cast<double>(layout.title_band_px) / o.height,
               0.03 + static_cast<double>(layout.scale_band_px) / o.height};
  FieldPicture p = render_field(prepared_box(), by_layer(), o);
  Annotation scaled = a;
  scaled.mm_per_pixel = p.mm_per_pixel;
  annotate(p.image, scaled);
  expect_matches_golden(p.image, "box-isometric-layers");
}

TEST(RenderGolden, CutawayFromTheFront) {
  RenderOptions o;
  o.width = 320;
  o.height = 200;
  o.camera.view = View::kUser;
  o.camera.direction = Eigen::Vector3f(0.4f, 1.0f, -0.5f);
  o.cut = Cutaway{Eigen::Vector3f(100, 100, 0), -Eigen::Vector3f::UnitY()};
  const FieldPicture p = render_field(prepared_box(), by_layer(), o);
  expect_matches_golden(p.image, "box-cutaway-layers");
}

}  // namespace
}  // namespace beadtwin::render
