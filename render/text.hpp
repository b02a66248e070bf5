// Text on images: TrueType fonts found on the system, drawn with FreeType onto a render::Image.
//
// Why FreeType and not OpenImageIO's ImageBufAlgo::render_text (which uses FreeType itself): the
// OpenImageIO 2.4 that Debian 12 ships decodes UTF-8 wrongly — every character outside ASCII comes out as
// another one ("°C" is drawn "0C", "µm" is "5m"; OpenImageIO issue #3933, fixed in later releases) — and the
// legends need "°C". Text is anti-aliased, hinted lightly (vertical only, as FreeType's "light" target does),
// composited over the image in display sRGB, and the same for every run and thread count.
#pragma once

#include <filesystem>
#include <memory>
#include <string_view>
#include <vector>

#include "render/image.hpp"

namespace beadtwin::render {

// Which of the two fonts a text is drawn in.
enum class FontWeight { kRegular, kBold };

// The standard places of a sans-serif TrueType font on Debian, best first: DejaVu Sans (fonts-dejavu-core),
// then Liberation Sans (fonts-liberation) and Noto Sans (fonts-noto-core).
std::vector<std::filesystem::path> default_font_paths(FontWeight weight);

// The first of `candidates` that is a regular file. Throws std::runtime_error listing every path tried
// and saying to install fonts-dejavu-core when none is.
std::filesystem::path find_font(const std::vector<std::filesystem::path>& candidates);

// A light halo drawn under text so that it reads over the part as well as over the background.
struct Halo {
  Rgb colour{0.97f, 0.97f, 0.98f};
  float opacity = 0.0f;  // 0 (no halo) .. 1
  int radius_px = 1;     // how far it reaches beyond the glyphs, >= 1
};

// Draws UTF-8 text with one regular and one bold font. Not safe to share between threads: make one per
// image (opening the fonts takes about a millisecond).
class TextRenderer {
 public:
  // Opens the two font files. Throws std::runtime_error naming a file that FreeType cannot read.
  TextRenderer(const std::filesystem::path& regular, const std::filesystem::path& bold);
  ~TextRenderer();
  TextRenderer(const TextRenderer&) = delete;
  TextRenderer& operator=(const TextRenderer&) = delete;

  // The advance width of `utf8` in pixels at `size_px` (the em size, >= 1): where the next character would
  // start. Invalid UTF-8 counts as U+FFFD.
  int width(std::string_view utf8, int size_px, FontWeight weight = FontWeight::kRegular) const;

  // Draws `utf8` with the left end of its baseline at (x, baseline_y), in pixels from the image's top left,
  // in `colour`, over `halo`. Whatever falls outside the image is clipped.
  void draw(Image& image, int x, int baseline_y, std::string_view utf8, int size_px, FontWeight weight,
            Rgb colour, const Halo& halo = {}) const;

 private:
  struct Fonts;
  std::unique_ptr<Fonts> fonts_;
};

}  // namespace beadtwin::render
