#include "render/image.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <set>
#include <stdexcept>
#include <string>

#include <csetjmp>
#include <cstdio>

#include <dlfcn.h>
#include <png.h>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "render/image_codec.hpp"

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

// The codec module, loaded the first time (render/image_codec.hpp says why): from beside the running
// program, else from where the build put it.
const codec::Api& image_codec() {
  static const codec::Api* api = [] {
    constexpr const char* kName = "libbeadtwin_image_codec.so";
    std::vector<std::filesystem::path> tried;
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) tried.push_back(self.parent_path() / kName);
    tried.emplace_back(BEADTWIN_IMAGE_CODEC);
    std::string errors;
    for (const std::filesystem::path& path : tried) {
      if (!std::filesystem::exists(path, ec)) continue;
      void* module = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (!module) {
        errors += std::string("; ") + dlerror();
        continue;
      }
      using Entry = const codec::Api* (*)();
      if (auto entry = reinterpret_cast<Entry>(dlsym(module, "beadtwin_image_codec"))) return entry();
      errors += "; " + path.string() + " has no beadtwin_image_codec";
    }
    std::string where;
    for (const std::filesystem::path& path : tried) where += (where.empty() ? "" : ", ") + path.string();
    throw InternalError("cannot load the image module " + std::string(kName) + " (looked for " + where + ")" +
                        errors);
  }();
  return *api;
}

// Writes `pixels` in the codec's `format` ("png", "openexr") to a temporary file beside `path`, renamed into
// place when complete. `label` names the format in messages.
void write_atomically(const char* format, const std::string& label, const std::filesystem::path& path,
                      codec::Pixels pixels) {
  AtomicPath out(path);
  pixels.software = "beadtwin " BEADTWIN_VERSION;
  const std::string why = image_codec().write(format, out.temp().string(), pixels);
  if (!why.empty()) fail("cannot write " + label, path, why);
  out.commit();
}

}  // namespace

namespace {

// libpng reports an error by calling this, which must not return: the message is kept and the writer jumps
// back to where it set the jump buffer.
struct PngErrors {
  std::jmp_buf jump;
  char message[256] = "";
};

[[noreturn]] void png_failed(png_structp png, png_const_charp message) {
  auto* errors = static_cast<PngErrors*>(png_get_error_ptr(png));
  std::snprintf(errors->message, sizeof errors->message, "%s", message);
  std::longjmp(errors->jump, 1);
}

void png_warned(png_structp, png_const_charp) {}

// `rows` (8-bit RGB, top row first) as a PNG on `file`, with the sRGB chunk and the Software text; an empty
// string or what libpng said went wrong. Plain C between setjmp and longjmp: nothing here has a destructor
// the jump could skip.
std::string write_png_rows(std::FILE* file, int width, int height, const std::vector<png_bytep>& rows,
                           const char* software) {
  PngErrors errors;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &errors, png_failed, png_warned);
  if (png == nullptr) return "libpng could not start";
  png_infop info = png_create_info_struct(png);
  if (info == nullptr || setjmp(errors.jump) != 0) {
    png_destroy_write_struct(&png, info != nullptr ? &info : nullptr);
    return errors.message[0] != '\0' ? errors.message : "libpng could not start";
  }
  png_init_io(png, file);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_text text{};
  text.compression = PNG_TEXT_COMPRESSION_NONE;
  text.key = const_cast<png_charp>("Software");
  text.text = const_cast<png_charp>(software);
  png_set_text(png, info, &text, 1);
  png_set_rows(png, info, const_cast<png_bytepp>(rows.data()));
  png_write_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
  png_destroy_write_struct(&png, &info);
  return {};
}

}  // namespace

// PNG through libpng itself rather than the codec module: the pictures of a run are PNGs, and loading the
// module (OpenImageIO and the 260 libraries it brings) is a noticeable part of a short run's CPU time.
void write_png(const Image& image, const std::filesystem::path& path) {
  check_not_empty(image, path);
  std::vector<std::uint8_t> bytes(image.pixels.size());
  std::transform(image.pixels.begin(), image.pixels.end(), bytes.begin(), to_byte);
  std::vector<png_bytep> rows(static_cast<std::size_t>(image.height));
  for (std::size_t y = 0; y < rows.size(); ++y)
    rows[y] = bytes.data() + y * static_cast<std::size_t>(image.width) * 3;
  AtomicPath out(path);
  std::FILE* file = std::fopen(out.temp().c_str(), "wb");
  if (file == nullptr) fail("cannot write PNG", path, std::strerror(errno));
  std::string why = write_png_rows(file, image.width, image.height, rows, "beadtwin " BEADTWIN_VERSION);
  if (std::fclose(file) != 0 && why.empty()) why = std::strerror(errno);
  if (!why.empty()) fail("cannot write PNG", path, why);
  out.commit();
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

  codec::Pixels pixels;
  pixels.width = image.width;
  pixels.height = image.height;
  pixels.channels = channels;
  pixels.is_float = true;
  pixels.data = interleaved.data();
  pixels.channel_names = {"R", "G", "B"};
  for (const ExtraChannel& channel : extra) {
    if (channel.name == "Z") pixels.z_channel = static_cast<int>(pixels.channel_names.size());
    pixels.channel_names.push_back(channel.name);
  }
  pixels.colour_space = "Linear";
  pixels.compression = "zip";
  write_atomically("openexr", "EXR", path, std::move(pixels));
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
  codec::ReadPixels raw;
  const std::string why = image_codec().read(path.string(), raw);
  if (!why.empty()) fail("cannot read image", path, why);
  const int channels = raw.channels;
  Image image(raw.width, raw.height);
  const std::size_t count = static_cast<std::size_t>(raw.width) * static_cast<std::size_t>(raw.height);
  for (std::size_t i = 0; i < count; ++i) {
    const float* src = &raw.data[i * static_cast<std::size_t>(channels)];
    for (int c = 0; c < 3; ++c)
      image.pixels[i * 3 + static_cast<std::size_t>(c)] = src[channels >= 3 ? c : 0];
  }
  return image;
}

}  // namespace beadtwin::render
