// Tests of the comparison sheet (render/sheet.hpp): the tiles land where they should, whole, with a
// caption above each.
#include "render/sheet.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace beadtwin::render {
namespace {

constexpr Rgb kRed{0.9f, 0.1f, 0.1f};
constexpr Rgb kBlue{0.1f, 0.2f, 0.9f};
constexpr Rgb kGreen{0.1f, 0.7f, 0.2f};

TEST(Sheet, TilesSideBySideUnderTheirCaptions) {
  const std::vector<Image> tiles = {Image(160, 100, kRed), Image(160, 100, kBlue), Image(160, 100, kGreen)};
  const Image sheet = compose_sheet(tiles, {"baseline", "thick walls", "slow"}, 3);
  EXPECT_EQ(sheet.width, 480);
  ASSERT_GT(sheet.height, 100);
  const int caption = sheet.height - 100;
  // Each tile whole, in order, below its caption band.
  EXPECT_EQ(sheet.at(10, caption + 5), kRed);
  EXPECT_EQ(sheet.at(159, sheet.height - 1), kRed);
  EXPECT_EQ(sheet.at(160, caption), kBlue);
  EXPECT_EQ(sheet.at(479, sheet.height - 1), kGreen);
  // Dark caption text in each band, centred over its tile; the band is white elsewhere.
  for (int t = 0; t < 3; ++t) {
    int dark = 0;
    for (int y = 0; y < caption; ++y)
      for (int x = t * 160; x < (t + 1) * 160; ++x) dark += sheet.at(x, y).r < 0.5f;
    EXPECT_GT(dark, 20) << t;
    EXPECT_EQ(sheet.at(t * 160 + 1, 1), (Rgb{1.0f, 1.0f, 1.0f}));
  }
}

TEST(Sheet, ChoosesColumnsNearWidescreen) {
  const std::vector<Image> four(4, Image(160, 100, kRed));
  const Image sheet = compose_sheet(four, {"a", "b", "c", "d"});
  // 160 x 100 tiles under ~24 px captions: 3 + 1 (480 x 248, 1.94) is nearer 16:9 than 2 x 2 (1.29) or
  // 4 x 1 (5.2); the empty place stays white.
  EXPECT_EQ(sheet.width, 480);
  EXPECT_EQ(sheet.at(400, sheet.height - 10), (Rgb{1.0f, 1.0f, 1.0f}));
}

TEST(Sheet, BadInputIsAnInputError) {
  EXPECT_THROW(compose_sheet({}, {}), InputError);
  EXPECT_THROW(compose_sheet({Image(10, 10)}, {"a", "b"}), InputError);
  EXPECT_THROW(compose_sheet({Image(10, 10), Image(12, 10)}, {"a", "b"}), InputError);
}

}  // namespace
}  // namespace beadtwin::render
