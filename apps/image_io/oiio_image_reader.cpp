// Reading any image OpenImageIO knows as float RGBA, for the plug-in's C interface (pbs_image_io.h).
#include "pbs_image_io.h"
#include "plugin_error.hpp"

#include <OpenImageIO/imageio.h>

#include <exception>
#include <memory>
#include <string>
#include <vector>

namespace {

using pbs::image_io::copyError;

std::unique_ptr<OIIO::ImageInput> openImage(const char* path, char* error, std::size_t errorSize) {
  // Values as stored: without this, OpenImageIO premultiplies the colour of straight-alpha formats
  // (PNG) by alpha as it reads.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto input = OIIO::ImageInput::open(path, &config);
  if (!input) copyError(OIIO::geterror(), error, errorSize);
  return input;
}

}  // namespace

extern "C" int pbs_read_image_size(const char* path, std::uint32_t* width, std::uint32_t* height, char* error,
                                   std::size_t errorSize) {
  try {
    const auto input = openImage(path, error, errorSize);
    if (!input) return 0;
    const OIIO::ImageSpec& spec = input->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1 || spec.nchannels <= 0) {
      copyError("not a 2D image with pixels", error, errorSize);
      return 0;
    }
    *width = std::uint32_t(spec.width);
    *height = std::uint32_t(spec.height);
    return 1;
  } catch (const std::exception& e) {  // nothing may unwind through the C interface
    copyError(e.what(), error, errorSize);
    return 0;
  }
}

extern "C" int pbs_read_image(const char* path, std::uint32_t width, std::uint32_t height, float* rgba, char* error,
                              std::size_t errorSize) {
  try {
    const auto input = openImage(path, error, errorSize);
    if (!input) return 0;
    const OIIO::ImageSpec spec = input->spec();
    if (spec.width != int(width) || spec.height != int(height) || spec.depth > 1 || spec.nchannels <= 0) {
      copyError("the image changed size while being read", error, errorSize);
      return 0;
    }
    const int channels = spec.nchannels;
    std::vector<float> file(std::size_t(width) * height * std::size_t(channels));
    if (!input->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, file.data())) {
      copyError(input->geterror(), error, errorSize);
      return 0;
    }
    // Alpha is the channel the file names so ("A", or the format's convention), else the second of
    // two (grey + alpha) or the fourth of four or more; colour is the first three of the others.
    int alpha = spec.alpha_channel;
    if (alpha < 0 || alpha >= channels) alpha = channels == 2 ? 1 : channels >= 4 ? 3 : -1;
    int colour[3] = {-1, -1, -1};
    int colours = 0;
    for (int c = 0; c < channels && colours < 3; ++c)
      if (c != alpha) colour[colours++] = c;
    if (colours == 1) colour[1] = colour[2] = colour[0];  // grey
    const std::size_t pixels = std::size_t(width) * height;
    for (std::size_t p = 0; p < pixels; ++p) {
      const float* in = file.data() + p * std::size_t(channels);
      float* out = rgba + 4 * p;
      for (int c = 0; c < 3; ++c) out[c] = colour[c] >= 0 ? in[colour[c]] : 0.0f;
      out[3] = alpha >= 0 ? in[alpha] : 1.0f;
    }
    return 1;
  } catch (const std::exception& e) {
    copyError(e.what(), error, errorSize);
    return 0;
  }
}
