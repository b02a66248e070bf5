// Integration: a toolpath deposited by sim::deposit, then rendered.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "core/bead.hpp"
#include "core/toolpath.hpp"
#include "render/render.hpp"
#include "sim/deposit.hpp"

namespace beadtwin::render {
namespace {

constexpr double kBeadWidth = 21.0;   // mm, an LSAM bead after the roller
constexpr double kLayerHeight = 5.0;  // mm
constexpr int kLayers = 16;
constexpr Rgb kMagenta{1, 0, 1};  // a background no shaded part pixel can take
constexpr Rgb kRed{0.85f, 0.25f, 0.20f};
constexpr Rgb kBlue{0.20f, 0.40f, 0.85f};

// A square box of walls, one bead per layer, corners joined: side `side` (bead centreline), from (0, 0).
Toolpath box_toolpath(double side, int layers) {
  Toolpath toolpath;
  const Eigen::Vector3d corners[] = {{0, 0, 0}, {side, 0, 0}, {side, side, 0}, {0, side, 0}};
  for (int layer = 0; layer < layers; ++layer) {
    const Eigen::Vector3d up(0, 0, (layer + 1) * kLayerHeight);  // a move's z is the top of its bead
    for (int c = 0; c < 4; ++c) {
      Move m;
      m.start = corners[c] + up;
      m.end = corners[(c + 1) % 4] + up;
      m.kind = MoveKind::kPrint;
      m.feature = Feature::kBoundary;
      m.pass = 0;
      m.roller_down = true;
      m.feed_mm_s = 100.0;
      m.bead_width_mm = kBeadWidth;
      m.layer_height_mm = kLayerHeight;
      m.layer = layer;
      m.volume_mm3 = bead_area_mm2(kBeadWidth, kLayerHeight) * m.length_mm();
      toolpath.moves.push_back(m);
    }
  }
  return toolpath;
}

float difference(Rgb a, Rgb b) {
  return std::max({std::abs(a.r - b.r), std::abs(a.g - b.g), std::abs(a.b - b.b)});
}

TEST(RenderPipeline, DepositedBoxShowsItsLayers) {
  const sim::Deposit deposit = sim::deposit(box_toolpath(300.0, kLayers));
  ASSERT_GT(deposit.active_voxels, 0u);

  RenderOptions o;
  o.width = 320;
  o.height = 200;
  o.camera.view = View::kFront;
  o.background = o.background_bottom = kMagenta;
  o.ground_shadow = false;
  const Image image = render_deposit(
      deposit, [](int layer) { return layer >= kLayers / 2 ? kRed : kBlue; }, o);

  // Down the middle column: red over the upper half of the wall, blue over the lower half.
  const int x = image.width / 2;
  int first = -1, last = -1;
  for (int y = 0; y < image.height; ++y)
    if (difference(image.at(x, y), kMagenta) > 0.3f) {
      if (first < 0) first = y;
      last = y;
    }
  ASSERT_GE(first, 0) << "the wall is not in the middle column";
  const int rows = last - first + 1;
  for (int y = first + 1; y < first + rows * 2 / 5; ++y) EXPECT_GT(image.at(x, y).r, image.at(x, y).b) << y;
  for (int y = last - rows * 2 / 5; y < last; ++y) EXPECT_GT(image.at(x, y).b, image.at(x, y).r) << y;

  // The isometric picture a person looks at, when BEADTWIN_RENDER_OUT names a directory.
  if (const char* out = std::getenv("BEADTWIN_RENDER_OUT")) {
    const auto verdict = [](int layer) {
      return layer < 2 ? kBlue : layer >= kLayers - 3 ? kRed : Rgb{0.35f, 0.70f, 0.40f};
    };
    write_png(render_deposit(deposit, verdict), std::filesystem::path(out) / "deposited-box-iso.png");
  }
}

}  // namespace
}  // namespace beadtwin::render
