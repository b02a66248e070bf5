#include "render/annotate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace beadtwin::render {
namespace {

// Text metrics as fractions of the em size, close to DejaVu Sans (ascender 0.93, descender 0.24, cap height
// 0.73) and Liberation / Noto Sans. The layout uses them rather than the font's own so that it is known
// before a font is opened and the same for every font.
int line_px(int size_px) {
  return static_cast<int>(std::lround(1.25 * size_px));
}
int baseline_px(int size_px) {
  return static_cast<int>(std::lround(0.95 * size_px));
}
// From a mark's y to the baseline of text centred on it: half the cap height.
int centre_to_baseline_px(int size_px) {
  return static_cast<int>(std::lround(0.36 * size_px));
}

struct Sizes {
  int margin, title, text;
};

// Sizes follow the image's height, but a very wide and short image takes them from its width, so the
// text does not crowd it: s = min(height, 0.625 width), the height of a 16:10 image that wide.
Sizes sizes_for(int width, int height) {
  const double s = std::min(static_cast<double>(height), 0.625 * width);
  return {std::max(4, static_cast<int>(std::lround(0.02 * s))),
          std::max(11, static_cast<int>(std::lround(0.034 * s))),
          std::max(9, static_cast<int>(std::lround(0.022 * s)))};
}

int stroke_px(const Sizes& s) {
  return std::max(1, static_cast<int>(std::lround(s.text / 16.0)));
}

// The colour bar's width, its tick marks' length and the gap between a tick and its label.
int bar_width_px(const Sizes& s) {
  return std::max(6, static_cast<int>(std::lround(1.1 * s.text)));
}
int tick_length_px(const Sizes& s) {
  return std::max(3, s.text / 3);
}
int tick_gap_px(const Sizes& s) {
  return s.text / 3;
}

// The scale bar: its thickness, and from the image's bottom edge up to the baseline of its label.
int scale_bar_thickness_px(const Sizes& s) {
  return std::max(2, static_cast<int>(std::lround(s.text / 7.0)));
}
int scale_label_rise_px(const Sizes& s) {
  return s.margin + scale_bar_thickness_px(s) + s.text / 4 + static_cast<int>(std::lround(0.3 * s.text));
}

void fill_rect(Image& image, int x0, int y0, int x1, int y1, Rgb colour) {  // [x0, x1) x [y0, y1), clipped
  for (int y = std::max(y0, 0); y < std::min(y1, image.height); ++y)
    for (int x = std::max(x0, 0); x < std::min(x1, image.width); ++x) image.set(x, y, colour);
}

// A frame `width` pixels wide just outside the rectangle [x0, x1) x [y0, y1).
void frame(Image& image, int x0, int y0, int x1, int y1, int width, Rgb colour) {
  fill_rect(image, x0 - width, y0 - width, x1 + width, y0, colour);
  fill_rect(image, x0 - width, y1, x1 + width, y1 + width, colour);
  fill_rect(image, x0 - width, y0, x0, y1, colour);
  fill_rect(image, x1, y0, x1 + width, y1, colour);
}

// Everything drawing needs: the image, the fonts, the sizes and the style.
struct Painter {
  Image& image;
  const TextRenderer& fonts;
  const Sizes& sizes;
  const AnnotationStyle& style;

  Halo halo(int size_px) const {
    Halo h = style.halo;
    h.radius_px = std::max(1, static_cast<int>(std::lround(size_px / 9.0)));
    return h;
  }
  void text(int x, int baseline, const std::string& s, int size_px, FontWeight weight, Rgb colour) const {
    fonts.draw(image, x, baseline, s, size_px, weight, colour, halo(size_px));
  }
  int width(const std::string& s, int size_px, FontWeight weight = FontWeight::kRegular) const {
    return fonts.width(s, size_px, weight);
  }

  // `s` broken at spaces into lines no wider than `max_px`; a word wider than that stands on its own line.
  std::vector<std::string> wrap(const std::string& s, int size_px, FontWeight weight, int max_px) const {
    std::vector<std::string> lines;
    std::string line;
    std::size_t start = 0;
    while (start <= s.size()) {
      std::size_t end = s.find(' ', start);
      if (end == std::string::npos) end = s.size();
      const std::string word = s.substr(start, end - start);
      const std::string longer = line.empty() ? word : line + " " + word;
      if (!line.empty() && width(longer, size_px, weight) > max_px) {
        lines.push_back(line);
        line = word;
      } else {
        line = longer;
      }
      start = end + 1;
    }
    if (!line.empty()) lines.push_back(line);
    return lines;
  }
};

void draw_title(const Painter& p, const Annotation& a) {
  const Sizes& s = p.sizes;
  if (!a.title.empty())
    p.text(s.margin, s.margin + baseline_px(s.title), a.title, s.title, FontWeight::kBold, p.style.text);
  if (!a.subtitle.empty()) {
    const int top = s.margin + (a.title.empty() ? 0 : line_px(s.title) + s.text / 4);
    p.text(s.margin, top + baseline_px(s.text), a.subtitle, s.text, FontWeight::kRegular, p.style.muted);
  }
}

// The colour bar's ticks: the legend's own values inside the scale, or round ones.
std::vector<double> bar_ticks(const Legend& legend, int bar_px, int text_px) {
  const ScalarScale& scale = *legend.scale;
  const double lo = std::min(scale.lo, scale.hi), hi = std::max(scale.lo, scale.hi);
  if (legend.ticks.empty()) {
    // Labels at least 1.6 lines apart, at most 8 of them.
    const int room = 1 + static_cast<int>(bar_px / (1.6 * line_px(text_px)));
    return nice_ticks(lo, hi, std::clamp(room, 2, 8));
  }
  std::vector<double> ticks;
  for (const double t : legend.ticks)
    if (std::isfinite(t) && t >= lo && t <= hi) ticks.push_back(t);
  return ticks;
}

// The tick labels as drawn: a true minus sign, as wide as a digit, for "-".
std::vector<std::string> bar_labels(const std::vector<double>& ticks) {
  std::vector<std::string> labels = tick_labels(ticks);
  for (std::string& label : labels)
    if (label.starts_with('-')) label.replace(0, 1, "\u2212");
  return labels;
}

// The legend's pieces placed in its panel, top to bottom, before anything is drawn: the panel is only as
// wide as layout_for() says, and a long label moves the whole legend left rather than off the image.
struct LegendPlan {
  int x = 0;  // left edge of the legend's content
  std::vector<std::string> title_lines, note_lines;
};

LegendPlan plan_legend(const Painter& p, const Legend& legend, int panel_px, int content_px) {
  const Sizes& s = p.sizes;
  LegendPlan plan;
  plan.title_lines = p.wrap(legend.title, s.text, FontWeight::kBold, content_px);
  plan.note_lines = p.wrap(legend.note, s.text, FontWeight::kRegular, content_px);
  int widest = 0;
  for (const auto& line : plan.title_lines)
    widest = std::max(widest, p.width(line, s.text, FontWeight::kBold));
  for (const auto& line : plan.note_lines) widest = std::max(widest, p.width(line, s.text));
  for (const auto& entry : legend.entries)
    widest = std::max(widest, s.text + s.text / 2 + p.width(entry.label, s.text));
  if (legend.scale) {
    // The bar's length is not known yet; its labels are as wide for any length that gives them room.
    for (const auto& label : bar_labels(bar_ticks(legend, p.image.height / 2, s.text)))
      widest = std::max(widest, 2 * stroke_px(s) + bar_width_px(s) + tick_length_px(s) + tick_gap_px(s) +
                                    p.width(label, s.text));
  }
  plan.x = p.image.width - panel_px + s.margin / 2;
  plan.x = std::max(0, std::min(plan.x, p.image.width - s.margin / 2 - widest));
  return plan;
}

// A vertical colour bar, hi at the top: row r of `length` rows shows the map at 1 - r / (length - 1), so the
// first and last rows are exactly the map's ends.
int draw_colour_bar(const Painter& p, const Legend& legend, int x, int top, int bottom) {
  const Sizes& s = p.sizes;
  const ScalarScale& scale = *legend.scale;
  const int bar_w = bar_width_px(s);
  const int length = std::max(bottom - top, 2);
  const bool reversed = scale.hi < scale.lo;
  for (int r = 0; r < length; ++r) {
    const double t = 1.0 - static_cast<double>(r) / (length - 1);
    fill_rect(p.image, x, top + r, x + bar_w, top + r + 1, scale.map.at(reversed ? 1.0 - t : t));
  }
  const int stroke = stroke_px(s);
  frame(p.image, x, top, x + bar_w, top + length, stroke, p.style.text);

  const std::vector<double> ticks = bar_ticks(legend, length, s.text);
  const std::vector<std::string> labels = bar_labels(ticks);
  const int tick_len = tick_length_px(s);
  const double lo = std::min(scale.lo, scale.hi), hi = std::max(scale.lo, scale.hi);
  for (std::size_t i = 0; i < ticks.size(); ++i) {
    const double f = hi > lo ? (ticks[i] - lo) / (hi - lo) : 0.5;
    const int y = top + static_cast<int>(std::lround((1.0 - f) * (length - 1)));
    fill_rect(p.image, x + bar_w, y - stroke / 2, x + bar_w + stroke + tick_len, y - stroke / 2 + stroke,
              p.style.text);
    p.text(x + bar_w + stroke + tick_len + tick_gap_px(s), y + centre_to_baseline_px(s.text), labels[i],
           s.text, FontWeight::kRegular, p.style.text);
  }
  return top + length + stroke;
}

int draw_swatches(const Painter& p, const Legend& legend, int x, int top) {
  const Sizes& s = p.sizes;
  const int swatch = std::max(6, static_cast<int>(std::lround(0.9 * s.text)));
  const int pitch = static_cast<int>(std::lround(1.45 * s.text));
  const int stroke = stroke_px(s);
  int y = top;
  for (const LegendEntry& entry : legend.entries) {
    fill_rect(p.image, x, y, x + swatch, y + swatch, entry.colour);
    frame(p.image, x, y, x + swatch, y + swatch, stroke, p.style.text);
    p.text(x + swatch + s.text / 2, y + swatch / 2 + centre_to_baseline_px(s.text), entry.label, s.text,
           FontWeight::kRegular, p.style.text);
    y += pitch;
  }
  return y;
}

void draw_legend(const Painter& p, const Legend& legend, int panel_px) {
  const Sizes& s = p.sizes;
  const int content_px = std::max(panel_px - s.margin / 2 - s.margin, 1);
  const LegendPlan plan = plan_legend(p, legend, panel_px, content_px);
  int y = s.margin;
  for (const auto& line : plan.title_lines) {
    p.text(plan.x, y + baseline_px(s.text), line, s.text, FontWeight::kBold, p.style.text);
    y += line_px(s.text);
  }
  y += static_cast<int>(std::lround(0.7 * s.text));  // room above the bar for the top tick's label

  if (legend.scale) {
    // The bar takes about half the image's height, less where the note below it needs the room.
    const int note_px =
        plan.note_lines.empty() ? 0 : s.text + static_cast<int>(plan.note_lines.size()) * line_px(s.text);
    const int limit = p.image.height - s.margin - note_px - s.text / 2;
    const int bottom = std::max(y + 8, std::min(y + p.image.height / 2, limit));
    y = draw_colour_bar(p, legend, plan.x + stroke_px(s), y, bottom) + s.text;
  } else {
    y = draw_swatches(p, legend, plan.x + stroke_px(s), y) + s.text / 2;
  }
  for (const auto& line : plan.note_lines) {
    p.text(plan.x, y + baseline_px(s.text), line, s.text, FontWeight::kRegular, p.style.muted);
    y += line_px(s.text);
  }
}

// The bar lies along the bottom margin with ticks rising at both ends; its label stands centred above it.
void draw_scale_bar(const Painter& p, const ScaleBar& bar) {
  const Sizes& s = p.sizes;
  const int thick = scale_bar_thickness_px(s);
  const int tick = std::max(4, static_cast<int>(std::lround(0.5 * s.text)));
  const int x0 = s.margin, x1 = s.margin + bar.length_px;
  const int bottom = p.image.height - s.margin;
  fill_rect(p.image, x0, bottom - thick, x1, bottom, p.style.text);
  fill_rect(p.image, x0, bottom - tick, x0 + thick, bottom, p.style.text);
  fill_rect(p.image, x1 - thick, bottom - tick, x1, bottom, p.style.text);
  const int label_w = p.width(bar.label, s.text);
  const int baseline = p.image.height - scale_label_rise_px(s);
  p.text(x0 + std::max(0, (bar.length_px - label_w) / 2), baseline, bar.label, s.text, FontWeight::kRegular,
         p.style.text);
}

bool has_text(const Annotation& a) {
  return !a.title.empty() || !a.subtitle.empty() || a.legend || a.mm_per_pixel > 0;
}

void validate(const Annotation& a) {
  if (!std::isfinite(a.mm_per_pixel))
    throw InputError("annotation: the image scale must be finite (mm per pixel), got " +
                     std::to_string(a.mm_per_pixel));
  if (a.legend && a.legend->scale &&
      (!std::isfinite(a.legend->scale->lo) || !std::isfinite(a.legend->scale->hi)))
    throw InputError("legend \"" + a.legend->title + "\": the colour scale's range must be finite, got " +
                     std::to_string(a.legend->scale->lo) + " .. " + std::to_string(a.legend->scale->hi));
}

std::string length_label(double length, const char* unit) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%g %s", length, unit);
  return buffer;
}

}  // namespace

AnnotationLayout layout_for(int width, int height, bool has_title, bool has_legend, bool has_scale) {
  BT_CHECK_OP(width, >=, 1);
  BT_CHECK_OP(height, >=, 1);
  const Sizes s = sizes_for(width, height);
  AnnotationLayout layout;
  layout.margin_px = s.margin;
  layout.title_px = s.title;
  layout.text_px = s.text;
  if (has_title)
    layout.title_band_px = s.margin + line_px(s.title) + s.text / 4 + line_px(s.text) + s.margin / 2;
  if (has_legend) {
    const double panel = std::clamp(0.18 * width, 8.0 * s.text, std::max(0.4 * width, 1.0));
    layout.legend_panel_px = std::min(static_cast<int>(std::lround(panel)), width);
  }
  if (has_scale) layout.scale_band_px = scale_label_rise_px(s) + baseline_px(s.text) + s.margin / 2;
  return layout;
}

AnnotationLayout layout_for(int width, int height, const Annotation& a) {
  AnnotationLayout layout = layout_for(width, height, false, a.legend.has_value(), a.mm_per_pixel > 0);
  const Sizes s = sizes_for(width, height);
  if (!a.title.empty()) layout.title_band_px = s.margin + line_px(s.title) + s.margin / 2;
  if (!a.subtitle.empty())
    layout.title_band_px =
        (a.title.empty() ? s.margin + s.margin / 2 : layout.title_band_px + s.text / 4) + line_px(s.text);
  return layout;
}

ScaleBar choose_scale_bar(double mm_per_pixel, int width_px, LengthUnit unit) {
  if (!(mm_per_pixel > 0) || !std::isfinite(mm_per_pixel))
    throw InputError("scale bar: the image scale must be positive and finite (mm per pixel), got " +
                     std::to_string(mm_per_pixel));
  if (width_px < 1)
    throw InputError("scale bar: the image width must be at least 1 pixel, got " + std::to_string(width_px));
  const double unit_mm = unit == LengthUnit::kInch ? 25.4 : 1.0;
  const double target = width_px * mm_per_pixel / 5.0 / unit_mm;  // a fifth of the width, in the unit
  const double decade = std::pow(10.0, std::floor(std::log10(target)));
  double best = decade;
  for (const double m : {1.0, 2.0, 5.0, 10.0}) {
    const double candidate = m * decade;
    if (std::abs(std::log(candidate / target)) < std::abs(std::log(best / target))) best = candidate;
  }
  ScaleBar bar;
  bar.length_mm = best * unit_mm;
  bar.length_px = static_cast<int>(std::lround(bar.length_mm / mm_per_pixel));
  if (unit == LengthUnit::kInch) {
    bar.label = length_label(best, "in");
  } else if (best >= 1000.0) {
    bar.label = length_label(best / 1000.0, "m");
  } else {
    bar.label = length_label(best, "mm");
  }
  return bar;
}

void annotate(Image& image, const Annotation& a) {
  validate(a);
  if (image.width <= 0 || image.height <= 0 || !has_text(a)) return;
  const TextRenderer fonts(find_font(a.style.regular_fonts), find_font(a.style.bold_fonts));
  const Sizes sizes = sizes_for(image.width, image.height);
  const Painter painter{image, fonts, sizes, a.style};
  const AnnotationLayout layout = layout_for(image.width, image.height, a);

  draw_title(painter, a);
  if (a.legend) draw_legend(painter, *a.legend, layout.legend_panel_px);
  if (a.mm_per_pixel > 0)
    draw_scale_bar(painter, choose_scale_bar(a.mm_per_pixel, image.width, a.length_unit));
}

}  // namespace beadtwin::render
