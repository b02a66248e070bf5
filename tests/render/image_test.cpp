#include "render/image.hpp"

#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
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

// The PNG says its colours are sRGB and which program wrote it, as another program reads it.
TEST_F(ImageFiles, PngSaysItIsSrgbAndWhoWroteIt) {
  const auto path = dir_ / "tagged.png";
  write_png(gradient(16, 8), path);
  auto in = OIIO::ImageInput::open(path.string());
  ASSERT_TRUE(in) << OIIO::geterror();
  const OIIO::ImageSpec& spec = in->spec();
  EXPECT_EQ(std::string(in->format_name()), "png");
  EXPECT_EQ(spec.nchannels, 3);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT8);
  EXPECT_EQ(spec.get_string_attribute("oiio:ColorSpace"), "sRGB");
  const std::string software(spec.get_string_attribute("Software"));
  EXPECT_EQ(software.rfind("beadtwin ", 0), 0u) << software;
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

// Every channel of an EXR by name, read with OpenImageIO as another program would.
std::map<std::string, std::vector<float>> read_channels(const std::filesystem::path& path,
                                                        std::string* format) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) throw std::runtime_error(OIIO::geterror());
  const OIIO::ImageSpec spec = in->spec();
  *format = in->format_name();
  std::vector<float> raw(static_cast<std::size_t>(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, raw.data()))
    throw std::runtime_error(in->geterror());
  std::map<std::string, std::vector<float>> channels;
  for (int c = 0; c < spec.nchannels; ++c)
    for (std::size_t i = 0; i < raw.size(); i += spec.nchannels)
      channels[spec.channelnames[c]].push_back(raw[i + c]);
  return channels;
}

TEST_F(ImageFiles, ExrHoldsLinearColoursAndRawChannels) {
  const Image image = gradient(16, 8);
  std::vector<float> value(16 * 8), depth(16 * 8);
  for (std::size_t i = 0; i < value.size(); ++i) {
    value[i] =
        i % 5 == 0 ? std::numeric_limits<float>::quiet_NaN() : 150.0f + 0.1234567f * static_cast<float>(i);
    depth[i] = 1000.0f + static_cast<float>(i);
  }
  const auto path = dir_ / "field.exr";
  write_exr(image, path, {{"value", value}, {"Z", depth}});

  std::string format;
  const auto channels = read_channels(path, &format);
  EXPECT_EQ(format, "openexr");
  ASSERT_EQ(channels.size(), 5u);
  for (const char* name : {"R", "G", "B", "value", "Z"}) ASSERT_EQ(channels.count(name), 1u) << name;
  const char* rgb[] = {"R", "G", "B"};
  for (std::size_t i = 0; i < value.size(); ++i) {
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(channels.at(rgb[c])[i], srgb_to_linear(image.pixels[i * 3 + c]), 1e-3f)
          << rgb[c] << " " << i;
    if (std::isnan(value[i])) {
      EXPECT_TRUE(std::isnan(channels.at("value")[i])) << i;
    } else {
      EXPECT_EQ(channels.at("value")[i], value[i]) << i;
    }
    EXPECT_EQ(channels.at("Z")[i], depth[i]) << i;
  }
  // Linear, not display values: mid grey is about 0.21, not 0.5.
  write_exr(Image(2, 2, {0.5f, 0.5f, 0.5f}), dir_ / "grey.exr");
  EXPECT_NEAR(read_channels(dir_ / "grey.exr", &format).at("G")[0], 0.214f, 1e-3f);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir_), {}), 2);  // no temporary files left
}

TEST_F(ImageFiles, ExrRejectsBadChannelsNamingThem) {
  const Image image = gradient(4, 3);
  const auto path = dir_ / "bad.exr";
  const auto message = [&](const std::vector<ExtraChannel>& extra) -> std::string {
    try {
      write_exr(image, path, extra);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  const std::string short_channel = message({{"value", std::vector<float>(11)}});
  EXPECT_NE(short_channel.find("value"), std::string::npos) << short_channel;
  EXPECT_NE(short_channel.find("11"), std::string::npos) << short_channel;
  EXPECT_NE(short_channel.find("12"), std::string::npos) << short_channel;
  EXPECT_NE(short_channel.find(path.string()), std::string::npos) << short_channel;
  EXPECT_NE(message({{"G", std::vector<float>(12)}}), "");
  EXPECT_NE(message({{"v", std::vector<float>(12)}, {"v", std::vector<float>(12)}}), "");
  EXPECT_NE(message({{"", std::vector<float>(12)}}), "");
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_THROW(write_exr(Image(), path), InputError);
  try {
    write_exr(image, dir_ / "missing" / "x.exr");
    FAIL() << "wrote into a missing directory";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("missing"), std::string::npos) << e.what();
  }
}

TEST_F(ImageFiles, WriteImageGoesByTheExtension) {
  const Image image = gradient(8, 8);
  const std::vector<ExtraChannel> extra = {{"value", std::vector<float>(64, 1.0f)}};
  std::string format;
  write_image(image, dir_ / "a.EXR", extra);
  EXPECT_EQ(read_channels(dir_ / "a.EXR", &format).count("value"), 1u);
  EXPECT_EQ(format, "openexr");
  write_image(image, dir_ / "b.png", extra);  // the colours alone
  EXPECT_EQ(read_channels(dir_ / "b.png", &format).size(), 3u);
  EXPECT_EQ(format, "png");
  EXPECT_THROW(write_image(image, dir_ / "c.tif"), InputError);
  EXPECT_THROW(write_image(image, dir_ / "noextension"), InputError);
}

}  // namespace
}  // namespace beadtwin::render
