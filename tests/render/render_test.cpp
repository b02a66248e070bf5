#include "render/render.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>

#include <unistd.h>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "core/error.hpp"
#include "tests/render/box_deposit.hpp"

namespace beadtwin::render {
namespace {

using testing::BoxPart;
using testing::make_box_deposit;
using testing::make_empty_deposit;

constexpr Rgb kGreen{0.30f, 0.72f, 0.35f};
constexpr Rgb kRed{0.85f, 0.25f, 0.20f};
constexpr Rgb kBlue{0.20f, 0.40f, 0.85f};
constexpr Rgb kMagenta{1.0f, 0.0f, 1.0f};  // a background no shaded part pixel can take

// Hue in degrees, 0..360 (red 0, green 120, blue 240); -1 for a grey.
double hue_deg(Rgb c) {
  const float hi = std::max({c.r, c.g, c.b}), lo = std::min({c.r, c.g, c.b});
  const float chroma = hi - lo;
  if (chroma < 1e-4f) return -1.0;
  double h = 0.0;
  if (hi == c.r)
    h = std::fmod((c.g - c.b) / chroma, 6.0);
  else if (hi == c.g)
    h = (c.b - c.r) / chroma + 2.0;
  else
    h = (c.r - c.g) / chroma + 4.0;
  h *= 60.0;
  return h < 0.0 ? h + 360.0 : h;
}

double hue_distance(double a, double b) {
  const double d = std::abs(a - b);
  return std::min(d, 360.0 - d);
}

float difference(Rgb a, Rgb b) {
  return std::max({std::abs(a.r - b.r), std::abs(a.g - b.g), std::abs(a.b - b.b)});
}

RenderOptions small_options(View view = View::kIsometric) {
  RenderOptions o;
  o.width = 320;
  o.height = 200;
  o.camera.view = view;
  o.background = o.background_bottom = kMagenta;
  o.ground_shadow = false;  // keep the background one colour: every other pixel is the part
  return o;
}

const sim::Deposit& box() {
  static const sim::Deposit deposit = make_box_deposit();
  return deposit;
}

TEST(RenderDeposit, BoxIsDrawnInItsLayerColour) {
  const Image image = render_deposit(
      box(), [](int) { return kGreen; }, small_options());
  ASSERT_EQ(image.width, 320);
  ASSERT_EQ(image.height, 200);

  const auto is_part = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < image.width && y < image.height &&
           difference(image.at(x, y), kMagenta) > 0.3f;
  };
  int part = 0, inner = 0, green_hue = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      if (!is_part(x, y)) continue;
      ++part;
      // Pixels on the outline mix the part with the background (green and magenta make grey); judge the
      // colour inside it. A few slivers of background seen through the box still mix in.
      if (!is_part(x - 1, y) || !is_part(x + 1, y) || !is_part(x, y - 1) || !is_part(x, y + 1)) continue;
      ++inner;
      const Rgb c = image.at(x, y);
      if (hue_distance(hue_deg(c), hue_deg(kGreen)) < 20.0) ++green_hue;
    }
  const double coverage = static_cast<double>(part) / (image.width * image.height);
  EXPECT_GT(coverage, 0.15) << "the box should fill a good part of the frame";
  EXPECT_LT(coverage, 0.9);
  EXPECT_GT(green_hue, 0.99 * inner) << green_hue << " of " << inner << " part pixels have the layer's hue";
}

TEST(RenderDeposit, FrontViewShowsUpperLayersAboveLowerOnes) {
  const BoxPart part;
  const int layers = static_cast<int>(part.height_mm / part.layer_height_mm);
  const auto colour = [&](int layer) { return layer >= layers / 2 ? kRed : kBlue; };
  const Image image = render_deposit(box(), colour, small_options(View::kFront));

  // Down the middle column: background, red (upper half of the wall), blue (lower half), background.
  const int x = image.width / 2;
  int first = -1, last = -1;
  for (int y = 0; y < image.height; ++y)
    if (difference(image.at(x, y), kMagenta) > 0.3f) {
      if (first < 0) first = y;
      last = y;
    }
  ASSERT_GE(first, 0) << "the part is not in the middle column";
  const int rows = last - first + 1;
  EXPECT_GT(rows, image.height / 4);
  for (int y = first + 1; y < first + rows * 2 / 5; ++y) {
    const Rgb c = image.at(x, y);
    EXPECT_GT(c.r, c.b) << "row " << y << " should be an upper (red) layer";
  }
  for (int y = last - rows * 2 / 5; y < last; ++y) {
    const Rgb c = image.at(x, y);
    EXPECT_GT(c.b, c.r) << "row " << y << " should be a lower (blue) layer";
  }
}

TEST(RenderDeposit, AsksForEachLayerPresentOnce) {
  std::map<int, int> calls;
  RenderOptions o = small_options();
  o.width = 16;
  o.height = 10;
  render_deposit(
      box(),
      [&](int layer) {
        ++calls[layer];
        return kGreen;
      },
      o);
  const BoxPart part;
  const int layers = static_cast<int>(part.height_mm / part.layer_height_mm);
  ASSERT_EQ(static_cast<int>(calls.size()), layers);
  for (const auto& [layer, count] : calls) {
    EXPECT_GE(layer, 0);
    EXPECT_LT(layer, layers);
    EXPECT_EQ(count, 1) << "layer " << layer;
  }
}

TEST(RenderDeposit, EveryViewShowsThePart) {
  for (const View view : {View::kIsometric, View::kTop, View::kFront}) {
    RenderOptions o = small_options(view);
    o.samples_per_pixel = 1;
    const Image image = render_deposit(
        box(), [](int) { return kGreen; }, o);
    int part = 0;
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x) part += difference(image.at(x, y), kMagenta) > 0.3f ? 1 : 0;
    EXPECT_GT(part, image.width * image.height / 10) << "view " << static_cast<int>(view);
  }
}

TEST(RenderDeposit, BackgroundIsAVerticalGradient) {
  RenderOptions o = small_options();
  o.background = {1.0f, 1.0f, 1.0f};
  o.background_bottom = {0.0f, 0.0f, 0.0f};
  const Image image = render_deposit(
      box(), [](int) { return kGreen; }, o);
  // The corners are background (the framing leaves a margin).
  EXPECT_GT(image.at(0, 0).r, 0.95f);
  EXPECT_LT(image.at(0, image.height - 1).r, 0.05f);
  EXPECT_GT(image.at(0, image.height / 4).r, image.at(0, image.height * 3 / 4).r);
}

// A 200 mm slab, two layers, with a 40 mm square tower of 5 mm layers in its middle, `height` tall.
sim::Deposit tower_on_slab(double height = 110.0) {
  const auto layer_at = [=](double x, double y, double z) {
    if (x < 0 || x > 200 || y < 0 || y > 200 || z < 0) return -1;
    if (z < 10) return static_cast<int>(z / 5);
    if (x < 80 || x > 120 || y < 80 || y > 120 || z > height) return -1;
    return static_cast<int>(z / 5);
  };
  return testing::voxelise(layer_at, {-5, -5, -5}, {205, 205, height + 5}, 2.5);
}

int count_changes(const Image& a, const Image& b, float sign) {
  int n = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) n += sign * (a.pixels[i] - b.pixels[i]) > 0.02f ? 1 : 0;
  return n;
}

TEST(RenderDeposit, TheKeyLightCastsShadows) {
  // From above, the tower's shadow lies on the slab beside it.
  const sim::Deposit deposit = tower_on_slab();
  const auto green = [](int) { return kGreen; };
  RenderOptions o = small_options(View::kTop);
  const Image with = render_deposit(deposit, green, o);
  o.shadows = false;
  const Image without = render_deposit(deposit, green, o);
  EXPECT_GT(count_changes(with, without, -1.0f), 300) << "the shadow should darken a patch of the slab";
  EXPECT_EQ(count_changes(with, without, +1.0f), 0) << "a shadow can only take light away";
}

TEST(RenderDeposit, GroundShadowFallsOnTheBackgroundOnly) {
  // A tower tall enough to throw its shadow past the slab, onto the bed (the isometric framing does not
  // depend on the ground shadow, so the part's pixels must not change).
  const sim::Deposit deposit = tower_on_slab(300.0);
  const auto green = [](int) { return kGreen; };
  RenderOptions o = small_options();
  o.samples_per_pixel = 1;  // every pixel all part or all background
  const Image off = render_deposit(deposit, green, o);
  o.ground_shadow = true;
  const Image on = render_deposit(deposit, green, o);
  int shadowed = 0;
  for (int y = 0; y < on.height; ++y)
    for (int x = 0; x < on.width; ++x) {
      if (on.at(x, y) == off.at(x, y)) continue;
      ++shadowed;
      EXPECT_LT(difference(off.at(x, y), kMagenta), 1e-5f)
          << x << "," << y << " changed but was not background";
      EXPECT_LT(on.at(x, y).r, off.at(x, y).r) << x << "," << y << " was not darkened";
    }
  EXPECT_GT(shadowed, 100);
}

TEST(RenderDeposit, TopViewFramesTheGroundShadowToo) {
  RenderOptions o = small_options(View::kTop);
  o.ground_shadow = true;
  const Image image = render_deposit(
      tower_on_slab(300.0), [](int) { return kGreen; }, o);
  int shadowed = 0, on_border = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const Rgb c = image.at(x, y);
      const bool shadow = c.g == 0.0f && c.r < 0.99f;  // darkened magenta: the part is never without green
      shadowed += shadow ? 1 : 0;
      on_border += shadow && (x == 0 || y == 0 || x == image.width - 1 || y == image.height - 1) ? 1 : 0;
    }
  EXPECT_GT(shadowed, 500);
  EXPECT_EQ(on_border, 0) << "the shadow runs out of the picture";
}

TEST(RenderDeposit, SameImageForAnyNumberOfThreads) {
  RenderOptions o = small_options();
  o.samples_per_pixel = 5;
  const auto colour = [](int layer) { return layer % 2 == 0 ? kRed : kBlue; };
  Image one, two;
  {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = render_deposit(box(), colour, o);
  }
  {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = render_deposit(box(), colour, o);
  }
  ASSERT_EQ(one.pixels.size(), two.pixels.size());
  std::size_t differing = 0;
  for (std::size_t i = 0; i < one.pixels.size(); ++i) differing += one.pixels[i] != two.pixels[i] ? 1 : 0;
  EXPECT_EQ(differing, 0u);
}

TEST(RenderDeposit, SameImageForAnyNumberOfThreadsWithSoftShadowsAndOcclusion) {
  RenderOptions o = small_options();
  o.samples_per_pixel = 6;
  o.ground_shadow = true;
  o.key_light_radius_deg = 8.0;
  o.ambient_occlusion = true;
  o.ambient_occlusion_samples = 3;
  const sim::Deposit deposit = tower_on_slab(150.0);
  const PreparedDeposit prepared(deposit);
  const auto colour = [](int layer) { return layer % 2 == 0 ? kRed : kBlue; };
  Image one, two;
  RenderStats stats_one, stats_two;
  {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = render_deposit(prepared, colour, o, &stats_one);
  }
  {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = render_deposit(prepared, colour, o, &stats_two);
  }
  ASSERT_EQ(one.pixels.size(), two.pixels.size());
  std::size_t differing = 0;
  for (std::size_t i = 0; i < one.pixels.size(); ++i) differing += one.pixels[i] != two.pixels[i] ? 1 : 0;
  EXPECT_EQ(differing, 0u);
  EXPECT_EQ(stats_one.shadow_rays, stats_two.shadow_rays);
  EXPECT_EQ(stats_one.occlusion_rays, stats_two.occlusion_rays);
  EXPECT_GT(stats_one.occlusion_rays, 0u);
}

// Where pixel (x, y) of a top view of `prepared` (no ground shadow) shows the bed-level point (x_mm, y_mm,
// z_mm).
std::pair<int, int> top_view_pixel(const PreparedDeposit& prepared, const RenderOptions& o, float x_mm,
                                   float y_mm, float z_mm) {
  const Camera camera =
      Camera::framed(View::kTop, prepared.surface().bounds, o.width, o.height, o.camera.field_of_view_deg);
  const Eigen::Vector2d uv = camera.project(Eigen::Vector3f(x_mm, y_mm, z_mm));
  return {static_cast<int>(uv.x() * o.width), static_cast<int>(uv.y() * o.height)};
}

float mean_green(const Image& image, int cx, int cy, int half) {
  float sum = 0.0f;
  int n = 0;
  for (int y = cy - half; y <= cy + half; ++y)
    for (int x = cx - half; x <= cx + half; ++x) {
      sum += image.at(x, y).g;
      ++n;
    }
  return sum / static_cast<float>(n);
}

TEST(RenderDeposit, AmbientOcclusionDarkensTheInsideCornerNotTheOpenFace) {
  // From above: the slab's top at the tower's foot (an inside corner) and far from it (open to the sky).
  const sim::Deposit deposit = tower_on_slab();
  const PreparedDeposit prepared(deposit);
  RenderOptions o = small_options(View::kTop);
  o.shadows = false;  // only the ambient light changes
  o.samples_per_pixel = 16;
  const auto green = [](int) { return kGreen; };
  const Image with = render_deposit(prepared, green, o);
  o.ambient_occlusion = false;
  const Image without = render_deposit(prepared, green, o);

  // The slab's top is at z = 10 mm; the tower spans x, y in 80..120 mm. A pixel here is about 1.1 mm.
  const auto [corner_x, corner_y] = top_view_pixel(prepared, o, 78.0f, 100.0f, 10.0f);
  const auto [open_x, open_y] = top_view_pixel(prepared, o, 30.0f, 100.0f, 10.0f);
  const float corner_drop =
      mean_green(without, corner_x, corner_y, 1) - mean_green(with, corner_x, corner_y, 1);
  const float open_drop = mean_green(without, open_x, open_y, 1) - mean_green(with, open_x, open_y, 1);
  EXPECT_GT(corner_drop, 0.02f) << "the inside corner should darken";
  EXPECT_NEAR(open_drop, 0.0f, 1e-6f) << "an open face sees nothing within the occlusion distance";
  EXPECT_EQ(count_changes(with, without, +1.0f), 0) << "occlusion can only take light away";

  // A longer reach darkens the corner further out.
  o.ambient_occlusion = true;
  o.ambient_occlusion_distance_mm = 40.0;
  const Image far = render_deposit(prepared, green, o);
  const auto [near_x, near_y] = top_view_pixel(prepared, o, 65.0f, 100.0f, 10.0f);  // 15 mm off the tower
  EXPECT_NEAR(mean_green(with, near_x, near_y, 1), mean_green(without, near_x, near_y, 1), 1e-6f);
  EXPECT_GT(mean_green(without, near_x, near_y, 1) - mean_green(far, near_x, near_y, 1), 0.01f);
}

TEST(RenderDeposit, AmbientOcclusionDarkensTheGrooveBetweenTwoBeads) {
  // Two round beads 10 mm across, side by side along x, seen from above: with occlusion the groove where
  // they touch (y = 0) is darker than without, their crowns (y = +-5 mm) are not.
  const auto two_beads = [](double x, double y, double z) {
    if (x < 0.0 || x > 60.0) return -1;
    const double a = std::hypot(y + 5.0, z - 5.0), b = std::hypot(y - 5.0, z - 5.0);
    return a <= 5.0 || b <= 5.0 ? 0 : -1;
  };
  const PreparedDeposit prepared(testing::voxelise(two_beads, {-2, -12, -2}, {62, 12, 12}, 1.0));
  RenderOptions o = small_options(View::kTop);
  o.samples_per_pixel = 8;
  o.ambient_occlusion_samples = 4;
  o.shadows = false;
  const auto green = [](int) { return kGreen; };
  const Image with = render_deposit(prepared, green, o);
  o.ambient_occlusion = false;
  const Image without = render_deposit(prepared, green, o);
  const auto darkening = [&](float y_mm) {
    const auto [x, y] = top_view_pixel(prepared, o, 30.0f, y_mm, 10.0f);
    return mean_green(without, x, y, 1) - mean_green(with, x, y, 1);
  };
  EXPECT_GT(darkening(0.0f), 0.03f) << "the groove";
  EXPECT_LT(darkening(5.0f), 0.01f) << "a crown";
  EXPECT_LT(darkening(-5.0f), 0.01f) << "a crown";
}

// The top view of the tower's shadow on the slab: pixels of the slab's open top lit, in full shadow and in
// between. `lit` is the picture without shadows, where all of the slab's top has one tone.
struct ShadowCensus {
  int lit = 0, dark = 0, between = 0;
};
ShadowCensus shadow_census(const Image& shadowed, const Image& lit, float slab_tone) {
  const auto on_slab = [&](int x, int y) { return std::abs(lit.at(x, y).g - slab_tone) < 0.002f; };
  float darkest = 1.0f;
  for (int y = 0; y < shadowed.height; ++y)
    for (int x = 0; x < shadowed.width; ++x)
      if (on_slab(x, y)) darkest = std::min(darkest, shadowed.at(x, y).g);
  ShadowCensus c;
  for (int y = 0; y < shadowed.height; ++y)
    for (int x = 0; x < shadowed.width; ++x) {
      if (!on_slab(x, y)) continue;
      const float s = shadowed.at(x, y).g;
      if (s > slab_tone - 0.01f)
        ++c.lit;
      else if (s < darkest + 0.01f)
        ++c.dark;
      else
        ++c.between;
    }
  return c;
}

TEST(RenderDeposit, ASoftKeyLightCastsAPenumbra) {
  const sim::Deposit deposit = tower_on_slab();
  const PreparedDeposit prepared(deposit);
  RenderOptions o = small_options(View::kTop);
  o.ambient_occlusion = false;  // only the key light changes
  o.samples_per_pixel = 16;
  const auto green = [](int) { return kGreen; };
  o.shadows = false;
  const Image unshadowed = render_deposit(prepared, green, o);
  o.shadows = true;
  o.key_light_radius_deg = 0.0;
  const auto [open_x, open_y] = top_view_pixel(prepared, o, 30.0f, 100.0f, 10.0f);
  const float slab = unshadowed.at(open_x, open_y).g;
  const ShadowCensus hard = shadow_census(render_deposit(prepared, green, o), unshadowed, slab);
  o.key_light_radius_deg = 5.0;
  const Image soft_image = render_deposit(prepared, green, o);
  const ShadowCensus soft = shadow_census(soft_image, unshadowed, slab);
  // Hard: only the pixels the shadow's outline crosses are in between. Soft: a band several pixels wide
  // (the tower's top edge is about 100 mm from its shadow: a 5 degree light blurs it over about 17 mm,
  // 15 pixels), with a full shadow still inside it.
  EXPECT_GT(hard.lit, 10000);
  EXPECT_GT(hard.dark, 300);
  EXPECT_GT(soft.dark, 100);
  EXPECT_GT(soft.between, 4 * hard.between) << soft.between << " against " << hard.between;
  EXPECT_EQ(count_changes(soft_image, unshadowed, +1.0f), 0) << "a shadow can only take light away";
}

TEST(RenderDeposit, CountsTheRaysItTraces) {
  const sim::Deposit deposit = tower_on_slab();
  const PreparedDeposit prepared(deposit);
  const auto green = [](int) { return kGreen; };
  RenderOptions o = small_options();
  o.samples_per_pixel = 3;
  o.shadows = false;
  o.ambient_occlusion = false;
  RenderStats plain;
  const Image image = render_deposit(prepared, green, o, &plain);
  EXPECT_EQ(plain.primary_rays, 320u * 200u * 3u);
  EXPECT_EQ(plain.shadow_rays, 0u);
  EXPECT_EQ(plain.occlusion_rays, 0u);
  EXPECT_EQ(plain.rays(), plain.primary_rays);
  // Pixels outside the outline of the part's box on the image are not traced; the part is inside it.
  EXPECT_GT(plain.primary_rays_outside, 0u);
  EXPECT_EQ(plain.rays_traced(), plain.rays() - plain.primary_rays_outside);

  o.ambient_occlusion = true;
  o.ambient_occlusion_samples = 1;
  RenderStats one;
  render_deposit(prepared, green, o, &one);
  o.ambient_occlusion_samples = 4;
  RenderStats four;
  render_deposit(prepared, green, o, &four);
  // One occlusion ray per sample that meets the part: about as many as the part's share of the pixels.
  int part = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) part += difference(image.at(x, y), kMagenta) > 0.3f ? 1 : 0;
  EXPECT_NEAR(static_cast<double>(one.occlusion_rays) / static_cast<double>(one.primary_rays),
              static_cast<double>(part) / (image.width * image.height), 0.02);
  EXPECT_LE(static_cast<std::uint64_t>(part) * 3u, plain.rays_traced()) << "part pixels were not traced";
  EXPECT_EQ(four.occlusion_rays, 4u * one.occlusion_rays);
  EXPECT_EQ(four.primary_rays, one.primary_rays);

  // Shadow rays: at most one per sample on the part, plus the bed's where the part may shadow it.
  o.shadows = true;
  RenderStats shadows;
  render_deposit(prepared, green, o, &shadows);
  EXPECT_GT(shadows.shadow_rays, 0u);
  EXPECT_LE(shadows.shadow_rays, one.occlusion_rays);
  o.ground_shadow = true;
  RenderStats ground;
  render_deposit(prepared, green, o, &ground);
  EXPECT_GT(ground.shadow_rays, shadows.shadow_rays);
  EXPECT_LE(ground.shadow_rays, ground.primary_rays);
}

TEST(RenderDeposit, APreparedDepositRendersLikeTheDeposit) {
  const auto colour = [](int layer) { return layer % 2 == 0 ? kRed : kBlue; };
  const PreparedDeposit prepared(box());
  for (const View view : {View::kIsometric, View::kTop}) {
    const RenderOptions o = small_options(view);
    EXPECT_TRUE(render_deposit(prepared, colour, o) == render_deposit(box(), colour, o));
  }
}

// Coloured point by point: red above the box's mid-height, blue below. The top view sees only the tops of
// the walls (red); the isometric view sees the sides' lower halves too (blue), and the same picture for
// any number of threads, although the colour function runs on the rendering's worker threads.
TEST(RenderDeposit, ColoursBySurfacePoint) {
  const BoxPart part;
  const auto by_height = [&](const Eigen::Vector3d& p, int) {
    return p.z() > 0.5 * part.height_mm ? kRed : kBlue;
  };
  const auto count_hues = [](const Image& image) {
    std::map<std::string, int> hues;
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x) {
        const Rgb c = image.at(x, y);
        if (difference(c, kMagenta) < 0.3f) continue;
        const double h = hue_deg(c);
        if (h >= 0 && hue_distance(h, hue_deg(kRed)) < 20) ++hues["red"];
        if (h >= 0 && hue_distance(h, hue_deg(kBlue)) < 20) ++hues["blue"];
      }
    return hues;
  };
  auto top = count_hues(render_deposit(box(), by_height, small_options(View::kTop)));
  EXPECT_GT(top["red"], 1000);
  EXPECT_EQ(top["blue"], 0);
  Image one, two;
  {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = render_deposit(box(), by_height, small_options());
  }
  {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = render_deposit(box(), by_height, small_options());
  }
  auto iso = count_hues(one);
  EXPECT_GT(iso["red"], 1000);
  EXPECT_GT(iso["blue"], 1000);
  ASSERT_EQ(one.pixels.size(), two.pixels.size());
  EXPECT_TRUE(one.pixels == two.pixels);
}

TEST(RenderDeposit, WritesAPngThatReadsBack) {
  const Image image = render_deposit(
      box(), [](int) { return kGreen; }, small_options());
  const auto dir =
      std::filesystem::temp_directory_path() / ("beadtwin-render-test-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto path = dir / "box.png";
  write_png(image, path);

  auto in = OIIO::ImageInput::open(path.string());
  ASSERT_TRUE(in) << OIIO::geterror();
  const OIIO::ImageSpec spec = in->spec();
  EXPECT_EQ(spec.width, image.width);
  EXPECT_EQ(spec.height, image.height);
  ASSERT_EQ(spec.nchannels, 3);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT8);
  std::vector<unsigned char> bytes(static_cast<std::size_t>(spec.width) * spec.height * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, bytes.data())) << in->geterror();
  in->close();
  for (const auto& [x, y] : {std::pair{0, 0}, {160, 100}, {319, 199}, {200, 80}, {100, 150}}) {
    const Rgb c = image.at(x, y);
    const std::size_t i = (static_cast<std::size_t>(y) * spec.width + x) * 3;
    EXPECT_NEAR(bytes[i] / 255.0, c.r, 0.5 / 255.0 + 1e-6) << x << "," << y;
    EXPECT_NEAR(bytes[i + 1] / 255.0, c.g, 0.5 / 255.0 + 1e-6) << x << "," << y;
    EXPECT_NEAR(bytes[i + 2] / 255.0, c.b, 0.5 / 255.0 + 1e-6) << x << "," << y;
  }
  std::filesystem::remove_all(dir);
}

TEST(RenderDeposit, EmptyDepositThrows) {
  const auto green = [](int) { return kGreen; };
  const sim::Deposit empty = make_empty_deposit();
  try {
    render_deposit(empty, green);
    FAIL() << "an empty deposit rendered";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nothing was deposited"), std::string::npos) << e.what();
  }
  sim::Deposit no_grids;
  EXPECT_THROW(render_deposit(no_grids, green), InputError);
  EXPECT_THROW(PreparedDeposit{empty}, InputError);
  EXPECT_THROW(PreparedDeposit{no_grids}, InputError);
}

TEST(RenderDeposit, DepositWithNoSurfaceThrows) {
  // Material everywhere less than half a voxel full: active voxels, but nothing at the 0.5 isosurface.
  sim::Deposit thin = make_empty_deposit();
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) {
      thin.fill->tree().setValue(openvdb::Coord(i, j, 0), 0.3f);
      thin.layer->tree().setValue(openvdb::Coord(i, j, 0), 0);
    }
  try {
    render_deposit(thin, [](int) { return kGreen; });
    FAIL() << "a deposit with no surface rendered";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nothing was deposited"), std::string::npos) << e.what();
  }
}

TEST(RenderDeposit, RejectsBadOptionsNamingThem) {
  RenderOptions o;
  o.width = 0;
  o.samples_per_pixel = 0;
  o.key_light_radius_deg = -1.0;
  o.ambient_occlusion_samples = 0;
  o.ambient_occlusion_distance_mm = -2.0;
  try {
    render_deposit(
        box(), [](int) { return kGreen; }, o);
    FAIL() << "bad options accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    for (const char* name : {"width", "samples_per_pixel", "key_light_radius_deg",
                             "ambient_occlusion_samples", "ambient_occlusion_distance_mm"})
      EXPECT_NE(what.find(name), std::string::npos) << name << ": " << what;
  }
}

// Writes the pictures a person looks at when BEADTWIN_RENDER_OUT names a directory; checks them anyway.
TEST(RenderDeposit, LsamBoxPictures) {
  const char* out = std::getenv("BEADTWIN_RENDER_OUT");
  BoxPart part;
  part.side_mm = 600.0;
  part.height_mm = out != nullptr ? 250.0 : 60.0;
  part.voxel_mm = out != nullptr ? 1.25 : 2.5;  // a quarter of the layer height shows the bead ridges
  const sim::Deposit deposit = make_box_deposit(part);
  const int layers = static_cast<int>(part.height_mm / part.layer_height_mm);
  const auto verdict = [&](int layer) {
    if (layer < 3) return kBlue;          // too cold: the first layers on a cold bed
    if (layer > layers - 4) return kRed;  // too hot: short layer time at the top
    return Rgb{0.35f, 0.70f, 0.40f};      // fine
  };
  for (const View view : {View::kIsometric, View::kTop, View::kFront}) {
    RenderOptions o;
    o.camera.view = view;
    if (out == nullptr) {
      o.width = 160;
      o.height = 100;
    }
    const Image image = render_deposit(deposit, verdict, o);
    int part_pixels = 0;  // across the middle row, against the background at its left end
    for (int x = 0; x < image.width; ++x)
      part_pixels += difference(image.at(x, image.height / 2), image.at(0, image.height / 2)) > 0.05f ? 1 : 0;
    EXPECT_GT(part_pixels, image.width / 40) << "view " << static_cast<int>(view);
    if (out != nullptr) {
      const char* names[] = {"iso", "top", "front"};
      write_png(image,
                std::filesystem::path(out) / (std::string("box-") + names[static_cast<int>(view)] + ".png"));
    }
  }
}

}  // namespace
}  // namespace beadtwin::render
