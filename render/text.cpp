#include "render/text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include <ft2build.h>
#include FT_FREETYPE_H

#include "core/error.hpp"

namespace beadtwin::render {

std::vector<std::filesystem::path> default_font_paths(FontWeight weight) {
  const bool bold = weight == FontWeight::kBold;
  return {
      bold ? "/usr/share/fonts/truetype/dejavu/DejaVuSans-Bold.ttf"
           : "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
      bold ? "/usr/share/fonts/truetype/liberation/LiberationSans-Bold.ttf"
           : "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
      bold ? "/usr/share/fonts/truetype/liberation2/LiberationSans-Bold.ttf"
           : "/usr/share/fonts/truetype/liberation2/LiberationSans-Regular.ttf",
      bold ? "/usr/share/fonts/truetype/noto/NotoSans-Bold.ttf"
           : "/usr/share/fonts/truetype/noto/NotoSans-Regular.ttf",
  };
}

std::filesystem::path find_font(const std::vector<std::filesystem::path>& candidates) {
  std::string tried;
  for (const auto& path : candidates) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(path, ec)) return path;
    tried += (tried.empty() ? "" : ", ") + path.string();
  }
  throw std::runtime_error("no font to draw the images' text: tried " + (tried.empty() ? "no paths" : tried) +
                           "; install the Debian package fonts-dejavu-core");
}

namespace {

// The next code point of `s` from `i`, advancing `i`; U+FFFD for a malformed sequence (one byte skipped).
char32_t next_code_point(std::string_view s, std::size_t& i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char lead = byte(i);
  int length = 0;
  char32_t cp = 0;
  if (lead < 0x80) {
    ++i;
    return lead;
  } else if ((lead & 0xE0) == 0xC0) {
    length = 2, cp = lead & 0x1F;
  } else if ((lead & 0xF0) == 0xE0) {
    length = 3, cp = lead & 0x0F;
  } else if ((lead & 0xF8) == 0xF0) {
    length = 4, cp = lead & 0x07;
  } else {
    ++i;
    return 0xFFFD;
  }
  if (i + static_cast<std::size_t>(length) > s.size()) {
    ++i;
    return 0xFFFD;
  }
  for (int k = 1; k < length; ++k) {
    const unsigned char c = byte(i + static_cast<std::size_t>(k));
    if ((c & 0xC0) != 0x80) {
      ++i;
      return 0xFFFD;
    }
    cp = (cp << 6) | (c & 0x3F);
  }
  i += static_cast<std::size_t>(length);
  return cp;
}

// Light hinting: glyphs snap to the pixel grid vertically only, which keeps their shapes and spacing while
// baselines and x-heights stay crisp.
constexpr FT_Int32 kLoadFlags = FT_LOAD_DEFAULT | FT_LOAD_TARGET_LIGHT;

// A coverage mask, 0..1, of `width` x `height` pixels whose top left lies at (x0, y0) in the image.
struct Mask {
  int x0 = 0, y0 = 0, width = 0, height = 0;
  std::vector<float> coverage;
  float at(int x, int y) const {
    if (x < 0 || y < 0 || x >= width || y >= height) return 0.0f;
    return coverage[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                    static_cast<std::size_t>(x)];
  }
};

// Blends `colour` over pixel (x, y) of `image` with opacity `alpha`, if the pixel is inside.
void blend(Image& image, int x, int y, Rgb colour, float alpha) {
  if (alpha <= 0.0f || x < 0 || y < 0 || x >= image.width || y >= image.height) return;
  const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) + x) * 3;
  float* p = &image.pixels[i];
  p[0] += alpha * (colour.r - p[0]);
  p[1] += alpha * (colour.g - p[1]);
  p[2] += alpha * (colour.b - p[2]);
}

}  // namespace

struct TextRenderer::Fonts {
  FT_Library library = nullptr;
  FT_Face regular = nullptr;
  FT_Face bold = nullptr;

  ~Fonts() {
    if (bold) FT_Done_Face(bold);
    if (regular) FT_Done_Face(regular);
    if (library) FT_Done_FreeType(library);
  }

  FT_Face open(const std::filesystem::path& path) const {
    FT_Face face = nullptr;
    if (const FT_Error error = FT_New_Face(library, path.c_str(), 0, &face))
      throw std::runtime_error("cannot read font " + path.string() + " (FreeType error " +
                               std::to_string(error) + ")");
    return face;
  }

  FT_Face face(FontWeight weight, int size_px) const {
    FT_Face f = weight == FontWeight::kBold ? bold : regular;
    const FT_Error error = FT_Set_Pixel_Sizes(f, 0, static_cast<FT_UInt>(std::max(size_px, 1)));
    if (error) throw InternalError("FreeType cannot size font to " + std::to_string(size_px) + " px");
    return f;
  }
};

TextRenderer::TextRenderer(const std::filesystem::path& regular, const std::filesystem::path& bold)
    : fonts_(std::make_unique<Fonts>()) {
  if (FT_Init_FreeType(&fonts_->library)) throw std::runtime_error("cannot start FreeType");
  fonts_->regular = fonts_->open(regular);
  fonts_->bold = fonts_->open(bold);
}

TextRenderer::~TextRenderer() = default;

namespace {

// Walks the glyphs of `utf8` along the baseline: calls visit(glyph_index, pen_x_26_6) for each and returns
// the pen position after the last, in 26.6 fixed point (1/64 pixel) as FreeType counts.
template <typename Visit>
FT_Pos walk(FT_Face face, std::string_view utf8, Visit&& visit) {
  FT_Pos pen = 0;
  FT_UInt previous = 0;
  for (std::size_t i = 0; i < utf8.size();) {
    const FT_UInt glyph = FT_Get_Char_Index(face, next_code_point(utf8, i));
    if (previous && glyph && FT_HAS_KERNING(face)) {
      FT_Vector kerning{};
      if (!FT_Get_Kerning(face, previous, glyph, FT_KERNING_DEFAULT, &kerning)) pen += kerning.x;
    }
    if (FT_Load_Glyph(face, glyph, kLoadFlags)) continue;  // a broken glyph is left out, not fatal
    visit(glyph, pen);
    pen += face->glyph->advance.x;
    previous = glyph;
  }
  return pen;
}

}  // namespace

int TextRenderer::width(std::string_view utf8, int size_px, FontWeight weight) const {
  const FT_Face face = fonts_->face(weight, size_px);
  const FT_Pos pen = walk(face, utf8, [](FT_UInt, FT_Pos) {});
  return static_cast<int>((pen + 32) >> 6);
}

void TextRenderer::draw(Image& image, int x, int baseline_y, std::string_view utf8, int size_px,
                        FontWeight weight, Rgb colour, const Halo& halo) const {
  const FT_Face face = fonts_->face(weight, size_px);
  const int pad = halo.opacity > 0.0f ? std::max(halo.radius_px, 1) : 0;

  // The mask spans the font's full line (ascender to descender) and the advance, with room for the halo
  // and for glyphs that reach left of their origin or beyond their advance.
  const auto& metrics = face->size->metrics;
  const int ascender = static_cast<int>((metrics.ascender + 63) >> 6);
  const int descender = static_cast<int>((-metrics.descender + 63) >> 6);
  const int overhang = size_px / 2 + 2;
  const int advance = width(utf8, size_px, weight);
  Mask mask;
  mask.x0 = x - overhang - pad;
  mask.y0 = baseline_y - ascender - overhang - pad;
  mask.width = advance + 2 * (overhang + pad);
  mask.height = ascender + descender + 2 * (overhang + pad);
  mask.coverage.assign(static_cast<std::size_t>(mask.width) * static_cast<std::size_t>(mask.height), 0.0f);

  walk(face, utf8, [&](FT_UInt, FT_Pos pen) {
    if (FT_Render_Glyph(face->glyph, FT_RENDER_MODE_NORMAL)) return;
    const FT_Bitmap& bitmap = face->glyph->bitmap;
    if (bitmap.pixel_mode != FT_PIXEL_MODE_GRAY || bitmap.num_grays < 2) return;
    const int left = x + static_cast<int>((pen + 32) >> 6) + face->glyph->bitmap_left - mask.x0;
    const int top = baseline_y - face->glyph->bitmap_top - mask.y0;
    const int pitch = std::abs(bitmap.pitch);
    for (int row = 0; row < static_cast<int>(bitmap.rows); ++row) {
      const int my = top + row;
      if (my < 0 || my >= mask.height) continue;
      const unsigned char* src = bitmap.buffer + static_cast<std::ptrdiff_t>(row) * pitch;
      for (int col = 0; col < static_cast<int>(bitmap.width); ++col) {
        const int mx = left + col;
        if (mx < 0 || mx >= mask.width) continue;
        float& c = mask.coverage[static_cast<std::size_t>(my) * static_cast<std::size_t>(mask.width) +
                                 static_cast<std::size_t>(mx)];
        c = std::max(c, static_cast<float>(src[col]) / static_cast<float>(bitmap.num_grays - 1));
      }
    }
  });

  if (pad > 0) {
    // The halo is the mask dilated by a disc of the halo's radius: a soft light outline that lifts dark
    // text off a dark or busy background and is invisible on the light one.
    const int r = pad;
    for (int my = 0; my < mask.height; ++my)
      for (int mx = 0; mx < mask.width; ++mx) {
        float reach = 0.0f;
        for (int dy = -r; dy <= r && reach < 1.0f; ++dy)
          for (int dx = -r; dx <= r; ++dx)
            if (dx * dx + dy * dy <= r * r + r) reach = std::max(reach, mask.at(mx + dx, my + dy));
        blend(image, mask.x0 + mx, mask.y0 + my, halo.colour, std::clamp(halo.opacity, 0.0f, 1.0f) * reach);
      }
  }
  for (int my = 0; my < mask.height; ++my)
    for (int mx = 0; mx < mask.width; ++mx) blend(image, mask.x0 + mx, mask.y0 + my, colour, mask.at(mx, my));
}

}  // namespace beadtwin::render
