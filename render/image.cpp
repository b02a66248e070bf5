#include "render/image.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <set>
#include <stdexcept>
#include <string>

#include <OpenImageIO/imageio.h>

#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace beadtwin::render {

Image::Image(int w, int h, Rgb fill) : width(w), height(h) {
  BT_CHECK_OP(w, >=, 0);
  BT_CHECK_OP(h, >=, 0);
  pixels.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
  for (std::size_t i = 0; i < pixels.size(); i += 3) {
    pixels[i] = fill.r;
    pixels[i + 1] = fill.g;
    pixels[i + 2] = fill.b;
  }
}

Rgb Image::at(int x, int y) const {
  BT_CHECK(x >= 0 && x < width && y >= 0 && y < height);
  const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + x) * 3;
  return {pixels[i], pixels[i + 1], pixels[i + 2]};
}

void Image::set(int x, int y, Rgb colour) {
  BT_CHECK(x >= 0 && x < width && y >= 0 && y < height);
  const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + x) * 3;
  pixels[i] = colour.r;
  pixels[i + 1] = colour.g;
  pixels[i + 2] = colour.b;
}

float srgb_to_linear(float encoded) {
  const float c = std::clamp(encoded, 0.0f, 1.0f);
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float linear) {
  const float c = std::clamp(linear, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

namespace {

std::uint8_t to_byte(float value) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0f, 1.0f) * 255.0f));
}

[[noreturn]] void fail(const std::string& what, const std::filesystem::path& path, const std::string& why) {
  throw std::runtime_error(what + " " + path.string() + (why.empty() ? std::string() : ": " + why));
}

void check_not_empty(const Image& image, const std::filesystem::path& path) {
  if (image.width <= 0 || image.height <= 0)
    throw InputError("cannot write " + path.string() + ": the image is empty (" +
                     std::to_string(image.width) + " x " + std::to_string(image.height) + " pixels)");
  BT_CHECK_OP(image.pixels.size(), ==, static_cast<std::size_t>(image.width) * image.height * 3);
}

// Writes `pixels` (of `type`, laid out as `spec` says) in OpenImageIO's `format` ("png", "openexr") to a
// temporary file beside `path`, renamed into place when complete. The format is named, not taken from the
// temporary name's extension. `label` names the format in messages.
void write_atomically(const char* format, const std::string& label, const std::filesystem::path& path,
                      const OIIO::ImageSpec& spec, OIIO::TypeDesc type, const void* pixels) {
  AtomicPath out(path);
  auto writer = OIIO::ImageOutput::create(format);
  if (!writer) fail("cannot write " + label, path, OIIO::geterror());
  if (!writer->open(out.temp().string(), spec)) fail("cannot write " + label, path, writer->geterror());
  if (!writer->write_image(type, pixels)) {
    const std::string why = writer->geterror();
    writer->close();
    fail("error while writing " + label, path, why);
  }
  if (!writer->close()) fail("error while writing " + label, path, writer->geterror());
  out.commit();
}

}  // namespace

void write_png(const Image& image, const std::filesystem::path& path) {
  check_not_empty(image, path);
  std::vector<std::uint8_t> bytes(image.pixels.size());
  std::transform(image.pixels.begin(), image.pixels.end(), bytes.begin(), to_byte);
  OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
  spec.attribute("oiio:ColorSpace", "sRGB");
  spec.attribute("Software", "beadtwin " BEADTWIN_VERSION);
  write_atomically("png", "PNG", path, spec, OIIO::TypeDesc::UINT8, bytes.data());
}

namespace {

void check_extra_channels(const Image& image, const std::filesystem::path& path,
                          const std::vector<ExtraChannel>& extra) {
  const std::size_t count = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  std::set<std::string> names{"R", "G", "B"};
  for (const ExtraChannel& channel : extra) {
    const std::string where = "cannot write " + path.string() + ": extra channel \"" + channel.name + "\" ";
    if (channel.name.empty())
      throw InputError("cannot write " + path.string() + ": an extra channel has no name");
    if (!names.insert(channel.name).second)
      throw InputError(where + "repeats the name of another channel (R, G and B are the colours)");
    if (channel.values.size() != count)
      throw InputError(where + "has " + std::to_string(channel.values.size()) + " values, the " +
                       std::to_string(image.width) + " x " + std::to_string(image.height) + " image needs " +
                       std::to_string(count));
  }
}

}  // namespace

void write_exr(const Image& image, const std::filesystem::path& path,
               const std::vector<ExtraChannel>& extra) {
  check_not_empty(image, path);
  check_extra_channels(image, path, extra);

  const int channels = 3 + static_cast<int>(extra.size());
  const std::size_t count = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  std::vector<float> interleaved(count * static_cast<std::size_t>(channels));
  for (std::size_t i = 0; i < count; ++i) {
    float* dst = &interleaved[i * static_cast<std::size_t>(channels)];
    for (int c = 0; c < 3; ++c) dst[c] = srgb_to_linear(image.pixels[i * 3 + static_cast<std::size_t>(c)]);
    for (std::size_t e = 0; e < extra.size(); ++e) dst[3 + e] = extra[e].values[i];
  }

  OIIO::ImageSpec spec(image.width, image.height, channels, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"R", "G", "B"};
  for (const ExtraChannel& channel : extra) {
    if (channel.name == "Z") spec.z_channel = static_cast<int>(spec.channelnames.size());
    spec.channelnames.push_back(channel.name);
  }
  spec.alpha_channel = -1;
  spec.attribute("oiio:ColorSpace", "Linear");
  spec.attribute("compression", "zip");
  spec.attribute("Software", "beadtwin " BEADTWIN_VERSION);
  write_atomically("openexr", "EXR", path, spec, OIIO::TypeDesc::FLOAT, interleaved.data());
}

void write_image(const Image& image, const std::filesystem::path& path,
                 const std::vector<ExtraChannel>& extra) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension == ".png") return write_png(image, path);
  if (extension == ".exr") return write_exr(image, path, extra);
  throw InputError("cannot write " + path.string() + ": unknown image type \"" + extension +
                   "\" (beadtwin writes .png and .exr)");
}

Image read_image(const std::filesystem::path& path) {
  auto reader = OIIO::ImageInput::open(path.string());
  if (!reader) fail("cannot read image", path, OIIO::geterror());
  const OIIO::ImageSpec& spec = reader->spec();
  const int channels = spec.nchannels;
  if (spec.width <= 0 || spec.height <= 0 || channels <= 0)
    fail("cannot read image", path, "it has no pixels");

  std::vector<float> raw(static_cast<std::size_t>(spec.width) * spec.height * channels);
  if (!reader->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, raw.data()))
    fail("cannot read image", path, reader->geterror());
  reader->close();

  Image image(spec.width, spec.height);
  const std::size_t count = static_cast<std::size_t>(spec.width) * spec.height;
  for (std::size_t i = 0; i < count; ++i) {
    const float* src = &raw[i * channels];
    for (int c = 0; c < 3; ++c) image.pixels[i * 3 + c] = src[channels >= 3 ? c : 0];
  }
  return image;
}

}  // namespace beadtwin::render
