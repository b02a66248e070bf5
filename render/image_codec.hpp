// The OpenImageIO half of image files: a module of its own (libbeadtwin_image_codec.so), loaded the first
// time an EXR is written or an image is read (PNGs are written with libpng: render/image.cpp).
//
// Why a module: OpenImageIO as Debian builds it brings 260 shared libraries (OpenCV, FFmpeg, GStreamer,
// DCMTK, ...). Linked into beadtwin, the dynamic loader would bind them all at every start, before any work,
// even for `beadtwin check` of a program that draws nothing (docs/PERFORMANCE.md). Loaded on demand, only
// runs that write pictures pay for it, once.
#pragma once

#include <string>
#include <vector>

namespace beadtwin::render::codec {

// Pixels to write: width x height x channels values, interleaved, row 0 at the top, 8-bit or 32-bit float.
struct Pixels {
  int width = 0, height = 0, channels = 0;
  bool is_float = false;
  const void* data = nullptr;
  std::vector<std::string> channel_names;  // empty: OpenImageIO's defaults
  int z_channel = -1;                      // the depth channel's index, or -1
  std::string colour_space;                // "sRGB", "Linear"
  std::string compression;                 // empty: the format's default
  std::string software;                    // the Software attribute
};

// A read image: width x height x channels floats, interleaved, as OpenImageIO converts them.
struct ReadPixels {
  int width = 0, height = 0, channels = 0;
  std::vector<float> data;
};

// The module's functions. Each returns an empty string or what went wrong, in OpenImageIO's words.
struct Api {
  // Writes `pixels` to `path` in `format` ("png", "openexr"), named rather than taken from the extension.
  std::string (*write)(const char* format, const std::string& path, const Pixels& pixels);
  std::string (*read)(const std::string& path, ReadPixels& out);
};

}  // namespace beadtwin::render::codec

// The module's one exported symbol.
extern "C" const beadtwin::render::codec::Api* beadtwin_image_codec();
