#include "render/image.hpp"

#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "core/error.hpp"

namespace beadtwin::render {
namespace {

class ImageFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("beadtwin-image-test-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

Image gradient(int width, int height) {
  Image image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      image.set(x, y,
                {static_cast<float>(x) / static_cast<float>(width - 1),
                 static_cast<float>(y) / static_cast<float>(height - 1), 0.25f});
  return image;
}

TEST(Image, SrgbTransferFunction) {
  EXPECT_FLOAT_EQ(srgb_to_linear(0.0f), 0.0f);
  EXPECT_FLOAT_EQ(srgb_to_linear(1.0f), 1.0f);
  EXPECT_NEAR(linear_to_srgb(0.5f), 0.7354f, 1e-4f);  // the usual 50 % grey
  EXPECT_NEAR(srgb_to_linear(0.5f), 0.2140f, 1e-4f);
  for (const float v : {0.001f, 0.02f, 0.3f, 0.9f}) EXPECT_NEAR(srgb_to_linear(linear_to_srgb(v)), v, 1e-5f);
  EXPECT_FLOAT_EQ(linear_to_srgb(2.0f), 1.0f);  // clamped
}

TEST(Image, PixelsAreAddressedFromTheTopLeft) {
  Image image(4, 3, {0.1f, 0.2f, 0.3f});
  image.set(3, 0, {1.0f, 0.0f, 0.5f});
  EXPECT_EQ(image.at(3, 0), (Rgb{1.0f, 0.0f, 0.5f}));
  EXPECT_EQ(image.at(0, 2), (Rgb{0.1f, 0.2f, 0.3f}));
  EXPECT_EQ(image.pixels[9], 1.0f);  // row 0, column 3
  EXPECT_THROW(image.at(4, 0), InternalError);
  EXPECT_THROW(image.at(0, -1), InternalError);
}

TEST_F(ImageFiles, PngRoundTripsTo8Bits) {
  const Image image = gradient(64, 48);
  const auto path = dir_ / "gradient.png";
  write_png(image, path);
  const Image back = read_image(path);
  ASSERT_EQ(back.width, 64);
  ASSERT_EQ(back.height, 48);
  for (std::size_t i = 0; i < image.pixels.size(); ++i)
    ASSERT_NEAR(back.pixels[i], image.pixels[i], 0.5f / 255.0f + 1e-6f) << "value " << i;
  // Only the target is left: the temporary file was renamed.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir_), {}), 1);
}

TEST_F(ImageFiles, ReplacesAnExistingFile) {
  const auto path = dir_ / "twice.png";
  write_png(gradient(8, 8), path);
  write_png(Image(5, 7, {1, 1, 1}), path);
  const Image back = read_image(path);
  EXPECT_EQ(back.width, 5);
  EXPECT_EQ(back.at(2, 3), (Rgb{1, 1, 1}));
}

TEST_F(ImageFiles, UnwritablePathThrowsNamingIt) {
  const auto path = dir_ / "no" / "such" / "dir" / "x.png";
  try {
    write_png(gradient(8, 8), path);
    FAIL() << "wrote into a missing directory";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
  EXPECT_THROW(write_png(Image(), dir_ / "empty.png"), InputError);
  EXPECT_THROW(read_image(dir_ / "missing.png"), std::runtime_error);
}

}  // namespace
}  // namespace beadtwin::render
