#include "render/annotate.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "core/error.hpp"
#include "render/text.hpp"

namespace beadtwin::render {
namespace {

// The renderer's background at the top of the image (RenderOptions::background).
constexpr Rgb kBackground{0.95f, 0.96f, 0.97f};

class Annotate : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("beadtwin-annotate-test-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

float chroma(Rgb c) {
  return std::max({c.r, c.g, c.b}) - std::min({c.r, c.g, c.b});
}
// Dark, grey: the annotations' text.
bool is_text_pixel(Rgb c) {
  return (c.r + c.g + c.b) / 3 < 0.45f && chroma(c) < 0.08f;
}

int count_changed(const Image& a, const Image& b, int x0, int y0, int x1, int y1) {
  int n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) n += a.at(x, y) == b.at(x, y) ? 0 : 1;
  return n;
}

Legend temperature_legend() {
  Legend legend;
  legend.title = "substrate temperature at deposition (°C)";
  legend.scale = ScalarScale{150.0, 300.0, ColourMap::viridis()};
  return legend;
}

// Where the colour bar is: the column of the right-hand panel with the longest run of coloured pixels, and
// that run's first and last rows.
struct Bar {
  int x0 = -1, x1 = -1, top = -1, bottom = -1;  // columns [x0, x1), rows [top, bottom]
};

Bar find_colour_bar(const Image& image, int panel_px) {
  Bar bar;
  int best = 0;
  for (int x = image.width - panel_px; x < image.width; ++x) {
    int run = 0;
    for (int y = 0; y < image.height; ++y) {
      run = chroma(image.at(x, y)) > 0.12f ? run + 1 : 0;
      if (run > best) {
        best = run;
        bar = {x, x + 1, y - run + 1, y};
      } else if (run == best && x == bar.x1 && y == bar.bottom) {
        bar.x1 = x + 1;  // the next column of the same bar
      }
    }
  }
  return bar;
}

// A continuous legend drawn, written as PNG and read back shows a colour bar whose ends
// are the map's ends, and labels its ticks.
TEST_F(Annotate, ContinuousLegendShowsTheMapsEndsAndLabelledTicks) {
  Annotation a;
  a.legend = temperature_legend();
  Image image(640, 400, kBackground);
  annotate(image, a);
  const auto path = dir_ / "legend.png";
  write_png(image, path);
  const Image back = read_image(path);

  const AnnotationLayout layout = layout_for(640, 400, a);
  const Bar bar = find_colour_bar(back, layout.legend_panel_px);
  ASSERT_GE(bar.x0, 640 - layout.legend_panel_px);
  ASSERT_GE(bar.bottom - bar.top, 400 / 4) << "no colour bar found";
  ASSERT_GE(bar.x1 - bar.x0, 5);
  const int x = (bar.x0 + bar.x1) / 2;
  const Rgb top = back.at(x, bar.top), bottom = back.at(x, bar.bottom);
  const Rgb hi = a.legend->scale->map.at(1.0), lo = a.legend->scale->map.at(0.0);
  constexpr float kTolerance = 2.0f / 255.0f;
  EXPECT_NEAR(top.r, hi.r, kTolerance);
  EXPECT_NEAR(top.g, hi.g, kTolerance);
  EXPECT_NEAR(top.b, hi.b, kTolerance);
  EXPECT_NEAR(bottom.r, lo.r, kTolerance);
  EXPECT_NEAR(bottom.g, lo.g, kTolerance);
  EXPECT_NEAR(bottom.b, lo.b, kTolerance);

  // Tick labels: dark text right of the bar and its tick marks, level with the bar.
  const auto text_right_of_bar = [&](const Image& img) {
    int n = 0;
    for (int y = std::max(bar.top - layout.text_px / 2, 0);
         y < std::min(bar.bottom + layout.text_px / 2, img.height); ++y)
      for (int px = bar.x1 + layout.text_px / 2 + 2; px < img.width; ++px)
        n += is_text_pixel(img.at(px, y)) ? 1 : 0;
    return n;
  };
  EXPECT_GT(text_right_of_bar(back), 40);
  Annotation unlabelled = a;
  unlabelled.legend->ticks = {1e9};  // outside the scale: no ticks
  Image plain(640, 400, kBackground);
  annotate(plain, unlabelled);
  EXPECT_EQ(text_right_of_bar(plain), 0);
}

TEST_F(Annotate, CategoricalLegendShowsEverySwatch) {
  Annotation a;
  a.legend = Legend{};
  a.legend->title = "fusion verdict";
  a.legend->entries = {{{0.85f, 0.28f, 0.23f}, "too hot"},
                       {{0.23f, 0.45f, 0.79f}, "too cold"},
                       {{0.36f, 0.68f, 0.42f}, "fuses"},
                       {{0.60f, 0.64f, 0.68f}, "no interface"}};
  Image image(640, 400, kBackground);
  annotate(image, a);
  const int panel = layout_for(640, 400, a).legend_panel_px;
  for (const LegendEntry& entry : a.legend->entries) {
    int n = 0;
    for (int y = 0; y < image.height; ++y)
      for (int x = image.width - panel; x < image.width; ++x) n += image.at(x, y) == entry.colour ? 1 : 0;
    EXPECT_GT(n, 40) << entry.label;
  }
}

TEST(AnnotateText, LegendMovesLeftRatherThanOffTheImage) {
  Annotation a;
  a.legend = Legend{};
  a.legend->entries = {{category_colour(0), "a label far wider than the legend's panel"}};
  const Image blank(320, 200, kBackground);
  Image image = blank;
  annotate(image, a);
  const int panel = layout_for(320, 200, a).legend_panel_px;
  EXPECT_GT(count_changed(image, blank, 0, 0, 320 - panel, 200), 0) << "the legend did not move left";
  EXPECT_EQ(count_changed(image, blank, 320 - 2, 0, 320, 200), 0) << "the label runs off the image";
}

TEST(AnnotateText, TitleStaysInItsBandAndDiffersByTitle) {
  Annotation a;
  a.title = "lsam-open-box: fusion verdict";
  a.subtitle = "variant slow-layers, isometric view";
  const Image blank(640, 400, kBackground);
  Image first = blank;
  annotate(first, a);
  const int band = layout_for(640, 400, a).title_band_px;
  EXPECT_GT(count_changed(first, blank, 0, 0, 640, band), 200);
  EXPECT_EQ(count_changed(first, blank, 0, band, 640, 400), 0) << "drawn below the title band";

  Annotation b = a;
  b.title = "lsam-open-box: sections";
  Image second = blank;
  annotate(second, b);
  EXPECT_GT(count_changed(first, second, 0, 0, 640, band), 50);

  Image again = blank;
  annotate(again, a);
  EXPECT_EQ(again, first);  // deterministic
}

TEST(AnnotateText, DrawsTheDegreeSignAsADegreeSign) {
  // OpenImageIO 2.4's render_text draws "°" as "0" (text.hpp); the ring must sit well above the baseline.
  const TextRenderer fonts(find_font(default_font_paths(FontWeight::kRegular)),
                           find_font(default_font_paths(FontWeight::kBold)));
  Image image(80, 80, {1, 1, 1});
  constexpr int kBaseline = 60, kSize = 40;
  fonts.draw(image, 10, kBaseline, "°", kSize, FontWeight::kRegular, {0, 0, 0});
  int dark = 0, lowest = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      if (image.at(x, y).r < 0.5f) ++dark, lowest = std::max(lowest, y);
  EXPECT_GT(dark, 20);
  EXPECT_LT(lowest, kBaseline - kSize / 3) << "the degree sign reaches down to the baseline, like a zero";

  Image zero(80, 80, {1, 1, 1}), degree(80, 80, {1, 1, 1});
  fonts.draw(zero, 5, kBaseline, "0C", 30, FontWeight::kRegular, {0, 0, 0});
  fonts.draw(degree, 5, kBaseline, "°C", 30, FontWeight::kRegular, {0, 0, 0});
  EXPECT_NE(zero, degree);
  EXPECT_GT(fonts.width("°C", 30), fonts.width("C", 30));
}

TEST(AnnotateText, MissingFontNamesThePathsTried) {
  Annotation a;
  a.title = "x";
  a.style.regular_fonts = {"/nonexistent/beadtwin/Sans.ttf", "/nonexistent/beadtwin/Other.ttf"};
  Image image(320, 200, kBackground);
  try {
    annotate(image, a);
    FAIL() << "drew without a font";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("/nonexistent/beadtwin/Sans.ttf"), std::string::npos) << message;
    EXPECT_NE(message.find("/nonexistent/beadtwin/Other.ttf"), std::string::npos) << message;
    EXPECT_NE(message.find("fonts-dejavu-core"), std::string::npos) << message;
  }
  // Nothing to draw needs no font.
  Annotation empty;
  empty.style.regular_fonts = a.style.regular_fonts;
  const Image before = image;
  EXPECT_NO_THROW(annotate(image, empty));
  EXPECT_EQ(image, before);
}

TEST(AnnotateText, RejectsAnUnusableScale) {
  Image image(320, 200, kBackground);
  Annotation a;
  a.mm_per_pixel = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(annotate(image, a), InputError);
  Annotation b;
  b.legend = temperature_legend();
  b.legend->scale->hi = std::numeric_limits<double>::infinity();
  EXPECT_THROW(annotate(image, b), InputError);
}

TEST(ScaleBar, PicksTheRoundLengthNearestAFifthOfTheWidth) {
  // 0.5 mm/px, 1920 px: a fifth is 192 mm, nearer 200 mm (x 1.04) than 100 mm (x 0.52).
  const ScaleBar a = choose_scale_bar(0.5, 1920);
  EXPECT_DOUBLE_EQ(a.length_mm, 200.0);
  EXPECT_EQ(a.length_px, 400);
  EXPECT_EQ(a.label, "200 mm");
  // 2 mm/px: 768 mm, nearer 1 m (x 1.30) than 500 mm (x 0.65).
  const ScaleBar b = choose_scale_bar(2.0, 1920);
  EXPECT_DOUBLE_EQ(b.length_mm, 1000.0);
  EXPECT_EQ(b.length_px, 500);
  EXPECT_EQ(b.label, "1 m");
  const ScaleBar c = choose_scale_bar(0.01, 320);  // 0.64 mm
  EXPECT_DOUBLE_EQ(c.length_mm, 0.5);
  EXPECT_EQ(c.label, "0.5 mm");
  const ScaleBar d = choose_scale_bar(0.5, 1920, LengthUnit::kInch);  // 7.56 in
  EXPECT_DOUBLE_EQ(d.length_mm, 254.0);
  EXPECT_EQ(d.label, "10 in");
  EXPECT_EQ(d.length_px, 508);

  for (double scale = 0.003; scale < 300.0; scale *= 1.37) {
    const ScaleBar bar = choose_scale_bar(scale, 1280);
    EXPECT_GE(bar.length_px, 0.2 * 1280 / std::sqrt(2.5) - 1) << scale;
    EXPECT_LE(bar.length_px, 0.2 * 1280 * std::sqrt(2.5) + 1) << scale;
    const double m = bar.length_mm / std::pow(10.0, std::floor(std::log10(bar.length_mm) + 1e-9));
    EXPECT_TRUE(std::abs(m - 1) < 1e-9 || std::abs(m - 2) < 1e-9 || std::abs(m - 5) < 1e-9) << bar.length_mm;
  }
  EXPECT_THROW(choose_scale_bar(0.0, 1920), InputError);
  EXPECT_THROW(choose_scale_bar(-1.0, 1920), InputError);
  EXPECT_THROW(choose_scale_bar(0.5, 0), InputError);
}

TEST(ScaleBar, IsDrawnAtTheBottomLeftAsLongAsItSays) {
  Annotation a;
  a.mm_per_pixel = 0.5;
  Image image(1280, 800, kBackground);
  annotate(image, a);
  const AnnotationLayout layout = layout_for(1280, 800, a);
  const ScaleBar bar = choose_scale_bar(0.5, 1280);
  // The longest dark horizontal run in the bottom band is the bar.
  int longest = 0, start = -1;
  for (int y = 800 - layout.scale_band_px; y < 800; ++y) {
    int run = 0;
    for (int x = 0; x < 1280; ++x) {
      run = is_text_pixel(image.at(x, y)) ? run + 1 : 0;
      if (run > longest) longest = run, start = x - run + 1;
    }
  }
  EXPECT_EQ(longest, bar.length_px);
  EXPECT_EQ(start, layout.margin_px);
  EXPECT_EQ(count_changed(image, Image(1280, 800, kBackground), 0, 0, 1280, 800 - layout.scale_band_px), 0);
}

TEST(AnnotationLayout, ScalesWithTheImage) {
  const AnnotationLayout small = layout_for(320, 200, true, true, true);
  const AnnotationLayout large = layout_for(1920, 1080, true, true, true);
  EXPECT_GE(small.text_px, 9);
  EXPECT_GE(small.title_px, 11);
  EXPECT_GT(large.text_px, 2 * small.text_px);
  EXPECT_GT(large.title_band_px, small.title_band_px);
  for (const AnnotationLayout& l : {small, large}) {
    EXPECT_GT(l.title_band_px, l.title_px);
    EXPECT_GT(l.scale_band_px, l.text_px);
    EXPECT_GT(l.legend_panel_px, 6 * l.text_px);
  }
  EXPECT_LE(small.legend_panel_px, 320 * 0.4 + 1);
  EXPECT_LT(small.title_band_px + small.scale_band_px, 200 / 3);
  const AnnotationLayout none = layout_for(1280, 800, false, false, false);
  EXPECT_EQ(none.title_band_px + none.legend_panel_px + none.scale_band_px, 0);
  Annotation title_only;
  title_only.title = "x";
  EXPECT_LT(layout_for(1280, 800, title_only).title_band_px,
            layout_for(1280, 800, true, false, false).title_band_px);
}

}  // namespace
}  // namespace beadtwin::render
