// libpng's simplified API: one call writes the whole image, errors come back in the image's message.
#include "png_writer.hpp"

#include <png.h>

#include <cstring>
#include <stdexcept>
#include <string>

namespace pbs::cli {
namespace {

png_image describe(std::uint32_t width, std::uint32_t height, int channels) {
  static constexpr png_uint_32 kFormats[] = {PNG_FORMAT_GRAY, PNG_FORMAT_GA, PNG_FORMAT_RGB, PNG_FORMAT_RGBA};
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = width;
  image.height = height;
  image.format = kFormats[channels - 1];
  image.flags = PNG_IMAGE_FLAG_FAST;
  return image;
}

}  // namespace

int writePng8(const char* path, std::uint32_t width, std::uint32_t height, int channels, const std::uint8_t* pixels,
              char* error, std::size_t errorSize) {
  png_image image = describe(width, height, channels);
  const png_int_32 rowStride = static_cast<png_int_32>(width) * channels;
  if (png_image_write_to_file(&image, path, 0, pixels, rowStride, nullptr) != 0) return 1;
  std::strncpy(error, image.message, errorSize - 1);
  error[errorSize - 1] = '\0';
  png_image_free(&image);
  return 0;
}

std::vector<std::uint8_t> encodePng8(std::uint32_t width, std::uint32_t height, int channels,
                                     const std::uint8_t* pixels) {
  png_image image = describe(width, height, channels);
  const png_int_32 rowStride = static_cast<png_int_32>(width) * channels;
  // The first call with no memory gives the size, the second writes.
  png_alloc_size_t size = 0;
  std::vector<std::uint8_t> bytes;
  if (png_image_write_to_memory(&image, nullptr, &size, 0, pixels, rowStride, nullptr) != 0) {
    bytes.resize(size);
    if (png_image_write_to_memory(&image, bytes.data(), &size, 0, pixels, rowStride, nullptr) != 0) {
      bytes.resize(size);
      return bytes;
    }
  }
  const std::string reason = image.message;
  png_image_free(&image);
  throw std::runtime_error("PNG: " + reason);
}

}  // namespace pbs::cli
