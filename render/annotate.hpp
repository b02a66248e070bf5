// Annotations on a rendered image: title, legend and scale bar, so that a picture explains itself.
//
// The title and an optional subtitle (scenario, variant, view) stand at the top left, the legend in a panel
// at the right — a colour bar with labelled ticks for a quantity, or swatches for categories — and the scale
// bar at the bottom left. layout_for() tells the renderer how much of the image to keep free for them;
// sizes follow the image's height, so a 320 x 200 test image and a 1920 x 1080 render are both legible.
// Text is dark grey over a light halo (it reads on the renderer's light background and over the part);
// fonts come from the system (text.hpp). The output is the same for every run and thread count.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "render/colormap.hpp"
#include "render/image.hpp"
#include "render/text.hpp"

namespace beadtwin::render {

// The unit a scale bar is labelled in.
enum class LengthUnit {
  kMetric,  // scale bar in mm, or in m from 1 m up
  kInch,    // scale bar in inches
};

// One category of a categorical legend: its colour and what it means ("too hot", "section 2").
struct LegendEntry {
  Rgb colour;
  std::string label;
};

// A legend: a colour bar when `scale` is set (a quantity), swatches for `entries` otherwise (categories).
struct Legend {
  std::string title;                 // with its unit, e.g. "substrate temperature at deposition (°C)"
  std::optional<ScalarScale> scale;  // lo at the bottom of the bar, hi at the top; both finite
  std::vector<double> ticks;         // values to label on the bar; empty: nice_ticks over the scale
  std::vector<LegendEntry> entries;  // without `scale`: one swatch each, top to bottom
  std::string note;  // under the legend, e.g. "3 % of the surface above 300 °C, drawn as 300"
};

// Colours and fonts of the annotations.
struct AnnotationStyle {
  Rgb text{0.13f, 0.14f, 0.16f};               // titles, labels, the scale bar and the colour bar's frame
  Rgb muted{0.30f, 0.32f, 0.35f};              // subtitle and notes
  Halo halo{{0.97f, 0.97f, 0.98f}, 0.65f, 1};  // radius_px is scaled with the text size
  // Fonts, tried in order (text.hpp: find_font): the first file that exists is used.
  std::vector<std::filesystem::path> regular_fonts = default_font_paths(FontWeight::kRegular);
  std::vector<std::filesystem::path> bold_fonts = default_font_paths(FontWeight::kBold);
};

// What is drawn on a picture.
struct Annotation {
  std::string title;     // UTF-8; empty: no title
  std::string subtitle;  // a second, smaller line under the title; empty: none
  std::optional<Legend> legend;
  double mm_per_pixel = 0.0;  // image scale at the part; <= 0: no scale bar
  LengthUnit length_unit = LengthUnit::kMetric;
  AnnotationStyle style;
};

// The parts of the image the annotations take, and their sizes, in pixels.
struct AnnotationLayout {
  int title_band_px = 0;    // rows at the top taken by the title and subtitle (0 without them)
  int legend_panel_px = 0;  // columns at the right taken by the legend (0 without one)
  int scale_band_px = 0;    // rows at the bottom taken by the scale bar (0 without one)
  int margin_px = 0;        // between the image's edges and the annotations
  int title_px = 0;         // the title's font size (em), >= 11
  int text_px = 0;          // every other text's font size (em), >= 9
};

// The layout of `annotation` on a width x height image (both >= 1). Depends only on the sizes and on which
// parts are present, not on the text, so the renderer can frame the part before anything is drawn. The
// second form reserves room for a subtitle with any title.
AnnotationLayout layout_for(int width, int height, const Annotation& annotation);
AnnotationLayout layout_for(int width, int height, bool has_title, bool has_legend, bool has_scale);

// A scale bar: a round length and how it is drawn.
struct ScaleBar {
  double length_mm = 0.0;
  int length_px = 0;
  std::string label;  // "200 mm", "1 m", "10 in"
};

// The scale bar for an image `width_px` wide at `mm_per_pixel` (> 0, finite): of the lengths 1, 2 or 5 x 10^n
// (mm, or inches with LengthUnit::kInch) the one nearest by ratio to a fifth of the width — so the bar is
// 13 % to 32 % of the width. At 0.5 mm per pixel and 1920 pixels a fifth is 192 mm: 200 mm, 400 pixels.
// Throws InputError for a scale that is not positive and finite or a width < 1.
ScaleBar choose_scale_bar(double mm_per_pixel, int width_px, LengthUnit unit = LengthUnit::kMetric);

// Draws the title, legend and scale bar of `annotation` onto `image`, in the places layout_for() gives.
// Nothing is drawn on an empty image. Throws InputError for a non-finite mm_per_pixel or a legend scale
// whose lo or hi is not finite, and std::runtime_error when there is text to draw and no font is found.
void annotate(Image& image, const Annotation& annotation);

}  // namespace beadtwin::render
