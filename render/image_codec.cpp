// The image codec module (render/image_codec.hpp): the only code that includes OpenImageIO.
#include "render/image_codec.hpp"

#include <OpenImageIO/imageio.h>

namespace {

using beadtwin::render::codec::Pixels;
using beadtwin::render::codec::ReadPixels;

// OpenImageIO's error, or `fallback` when it says nothing: an empty string would read as success.
std::string failed(std::string why, const char* fallback) {
  return why.empty() ? std::string(fallback) : why;
}

std::string write(const char* format, const std::string& path, const Pixels& pixels) {
  const OIIO::TypeDesc type = pixels.is_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
  OIIO::ImageSpec spec(pixels.width, pixels.height, pixels.channels, type);
  if (!pixels.channel_names.empty()) spec.channelnames = pixels.channel_names;
  spec.z_channel = pixels.z_channel;
  spec.alpha_channel = -1;
  if (!pixels.colour_space.empty()) spec.attribute("oiio:ColorSpace", pixels.colour_space);
  if (!pixels.compression.empty()) spec.attribute("compression", pixels.compression);
  if (!pixels.software.empty()) spec.attribute("Software", pixels.software);
  auto writer = OIIO::ImageOutput::create(format);
  if (!writer) return failed(OIIO::geterror(), "OpenImageIO has no writer for this format");
  if (!writer->open(path, spec)) return failed(writer->geterror(), "the file could not be opened");
  if (!writer->write_image(type, pixels.data)) {
    const std::string why = writer->geterror();
    writer->close();
    return failed(why, "the image was not written");
  }
  if (!writer->close()) return failed(writer->geterror(), "the file could not be closed");
  return {};
}

std::string read(const std::string& path, ReadPixels& out) {
  auto reader = OIIO::ImageInput::open(path);
  if (!reader) return failed(OIIO::geterror(), "the file could not be opened");
  const OIIO::ImageSpec& spec = reader->spec();
  out.width = spec.width;
  out.height = spec.height;
  out.channels = spec.nchannels;
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) return "it has no pixels";
  out.data.resize(static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height) *
                  static_cast<std::size_t>(spec.nchannels));
  if (!reader->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, out.data.data()))
    return failed(reader->geterror(), "the pixels could not be read");
  reader->close();
  return {};
}

constexpr beadtwin::render::codec::Api kApi{&write, &read};

}  // namespace

extern "C" const beadtwin::render::codec::Api* beadtwin_image_codec() {
  return &kApi;
}
