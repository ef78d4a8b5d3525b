// The one place that links OpenImageIO: a plug-in module the `pbs` binary loads only when it writes or
// reads an image. OpenImageIO pulls in some 250 shared libraries whose loading costs about 0.15–0.25 s
// of process start-up, which commands that touch no image (surfelize, info, analyze) should not pay.
#include "pbs_image_io.h"
#include "plugin_error.hpp"

#include <OpenImageIO/imageio.h>

#include <exception>
#include <string>

namespace {

using pbs::image_io::copyError;

int writeImage(const char* path, std::uint32_t width, std::uint32_t height, int channels, OIIO::TypeDesc type,
               const void* pixels, char* error, std::size_t errorSize) {
  try {
    auto output = OIIO::ImageOutput::create(path);
    if (!output) {
      copyError(OIIO::geterror(), error, errorSize);
      return 0;
    }
    // The file's type is the data's where the format has it; open() falls back to the nearest it
    // supports (PNG takes float as 8 bits) and write_image converts.
    OIIO::ImageSpec spec(int(width), int(height), channels, type);
    // pbs colour is straight, not premultiplied by alpha (coverage): stored as given, so PNG's
    // writer does not divide it by alpha (which would blank the colour behind alpha 0).
    spec.attribute("oiio:UnassociatedAlpha", 1);
    if (!output->open(path, spec) || !output->write_image(type, pixels) || !output->close()) {
      copyError(output->geterror(), error, errorSize);
      return 0;
    }
    return 1;
  } catch (const std::exception& e) {  // nothing may unwind through the C interface
    copyError(e.what(), error, errorSize);
    return 0;
  }
}

}  // namespace

extern "C" int pbs_write_image8(const char* path, std::uint32_t width, std::uint32_t height, int channels,
                                const std::uint8_t* pixels, char* error, std::size_t errorSize) {
  return writeImage(path, width, height, channels, OIIO::TypeDesc::UINT8, pixels, error, errorSize);
}

extern "C" int pbs_write_image_float(const char* path, std::uint32_t width, std::uint32_t height, int channels,
                                     const float* pixels, char* error, std::size_t errorSize) {
  return writeImage(path, width, height, channels, OIIO::TypeDesc::FLOAT, pixels, error, errorSize);
}
