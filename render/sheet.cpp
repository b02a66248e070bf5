#include "render/sheet.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "render/text.hpp"

namespace beadtwin::render {
namespace {

constexpr Rgb kPage{1.0f, 1.0f, 1.0f};
constexpr Rgb kCaption{0.13f, 0.14f, 0.16f};

// The number of columns whose sheet is nearest to 16:9 (by the ratio's logarithm).
int best_columns(int count, int tile_w, int tile_h, int caption_h) {
  int best = 1;
  double best_error = 1e300;
  for (int c = 1; c <= count; ++c) {
    const int rows = (count + c - 1) / c;
    const double aspect = static_cast<double>(c * tile_w) / (rows * (tile_h + caption_h));
    const double error = std::abs(std::log(aspect / (16.0 / 9.0)));
    if (error < best_error - 1e-12) best = c, best_error = error;
  }
  return best;
}

}  // namespace

Image compose_sheet(const std::vector<Image>& tiles, const std::vector<std::string>& captions, int columns) {
  if (tiles.empty()) throw InputError({}, "sheet", "no pictures to put side by side");
  if (captions.size() != tiles.size())
    throw InputError({}, "sheet",
                     "there are " + std::to_string(tiles.size()) + " pictures and " +
                         std::to_string(captions.size()) + " captions");
  const int w = tiles.front().width, h = tiles.front().height;
  for (const Image& t : tiles)
    if (t.width != w || t.height != h || w <= 0 || h <= 0)
      throw InputError({}, "sheet", "the pictures side by side must all have one size");
  const int text_px = std::max(12, static_cast<int>(std::lround(0.035 * std::min(h, w))));
  const int caption_h = 2 * text_px;
  const int count = static_cast<int>(tiles.size());
  const int cols = columns > 0 ? std::min(columns, count) : best_columns(count, w, h, caption_h);
  const int rows = (count + cols - 1) / cols;
  Image sheet(cols * w, rows * (h + caption_h), kPage);
  const TextRenderer text(find_font(default_font_paths(FontWeight::kRegular)),
                          find_font(default_font_paths(FontWeight::kBold)));
  for (int i = 0; i < count; ++i) {
    const int x0 = (i % cols) * w, y0 = (i / cols) * (h + caption_h);
    const Image& tile = tiles[static_cast<std::size_t>(i)];
    for (int y = 0; y < h; ++y)
      std::copy_n(
          tile.pixels.begin() + static_cast<std::ptrdiff_t>(3 * y * w), 3 * w,
          sheet.pixels.begin() + static_cast<std::ptrdiff_t>(3 * ((y0 + caption_h + y) * sheet.width + x0)));
    const std::string& caption = captions[static_cast<std::size_t>(i)];
    const int width = text.width(caption, text_px, FontWeight::kBold);
    text.draw(sheet, x0 + std::max(0, (w - width) / 2), y0 + caption_h - text_px / 2, caption, text_px,
              FontWeight::kBold, kCaption);
  }
  return sheet;
}

}  // namespace beadtwin::render
