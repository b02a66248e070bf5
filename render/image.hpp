// Images of the render stage and their files.
//
// An Image holds display-encoded sRGB (what a screen shows and a PNG stores), 0..1 per channel, three
// channels interleaved, row 0 at the top. Shading happens in linear light; srgb_to_linear and
// linear_to_srgb convert at the two ends. PNGs are written with libpng; EXRs, and every file read, go
// through OpenImageIO (in a module loaded on first use, render/image_codec.hpp). Files are written
// atomically, so an interrupted run never leaves half an image behind.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace beadtwin::render {

// A display sRGB colour, 0..1 per channel.
struct Rgb {
  float r = 0, g = 0, b = 0;
  friend bool operator==(const Rgb&, const Rgb&) = default;
};

// An image in display sRGB (the values a PNG stores).
struct Image {
  int width = 0, height = 0;
  std::vector<float> pixels;  // display sRGB, RGB interleaved, row 0 at the top; width * height * 3 values

  Image() = default;
  // A width x height image filled with `fill`. Preconditions: width, height >= 0.
  Image(int w, int h, Rgb fill = {});

  // Pixel (x, y), x to the right, y down from the top row. Throws InternalError outside the image.
  Rgb at(int x, int y) const;
  void set(int x, int y, Rgb colour);  // sets pixel (x, y); throws as at() outside the image

  friend bool operator==(const Image&, const Image&) = default;
};

// The sRGB transfer function (IEC 61966-2-1) and its inverse, for one channel in 0..1.
float srgb_to_linear(float encoded);
float linear_to_srgb(float linear);

// Writes `image` as an 8-bit sRGB PNG (with the sRGB chunk and beadtwin's name as its Software) through
// libpng: to a temporary file beside `path`, renamed into place when complete. Throws InputError for an empty
// image and std::runtime_error naming the path when the file cannot be written.
void write_png(const Image& image, const std::filesystem::path& path);

// A named float channel written beside the colours of an EXR: raw values for other programs, such as the
// field value under each pixel ("value", NaN where the ray misses the part) or the depth ("Z", mm).
struct ExtraChannel {
  std::string name;           // not empty, not R, G or B, unique within one file
  std::vector<float> values;  // one per pixel, row 0 at the top: width * height values; NaN is kept
};

// Writes `image` as an OpenEXR file through OpenImageIO: channels R, G, B in linear light (the EXR
// convention: `image`'s display sRGB decoded by srgb_to_linear) as 32-bit floats, then `extra` channels as
// given, zip-compressed. Atomic like write_png. Throws InputError for an empty image and for an extra
// channel of the wrong size or with an empty, reserved or repeated name (naming the channel, the sizes and
// the path), and std::runtime_error naming the path when the file cannot be written.
void write_exr(const Image& image, const std::filesystem::path& path,
               const std::vector<ExtraChannel>& extra = {});

// write_png or write_exr by the extension of `path` (.png or .exr, in any case); `extra` channels go into an
// EXR only: a PNG holds the colours alone. Throws InputError naming the path for any other extension.
void write_image(const Image& image, const std::filesystem::path& path,
                 const std::vector<ExtraChannel>& extra = {});

// Reads any image OpenImageIO knows (PNG, EXR, ...) into display values 0..1: grey is copied to the three
// channels, alpha and further channels are dropped, 8- and 16-bit values are scaled to 0..1 and nothing is
// colour converted. For tests and reference-image comparison. Throws std::runtime_error naming the path.
Image read_image(const std::filesystem::path& path);

}  // namespace beadtwin::render
