// Image input and output through the OpenImageIO plug-in (8-bit PNG through libpng, in the process),
// with the temporary-name-then-rename rule of every pbs output.
#include "image_files.hpp"

#include "pbs_image_io.h"
#include "png_writer.hpp"

#include <pbs/scene/input_error.hpp>

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <system_error>

namespace pbs::cli {
namespace {

// libpbs_image_io.so beside the running binary, loaded once and kept for the life of the process.
void* imageLibrary() {
  static void* const library = [] {
    const std::filesystem::path module =
        std::filesystem::read_symlink("/proc/self/exe").parent_path() / "libpbs_image_io.so";
    void* handle = dlopen(module.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) throw std::runtime_error(std::string("cannot load the image plug-in: ") + dlerror());
    return handle;
  }();
  return library;
}

template <typename Function>
Function imageFunction(const char* name) {
  auto function = reinterpret_cast<Function>(dlsym(imageLibrary(), name));
  if (!function) throw std::runtime_error(std::string("the image plug-in has no ") + name);
  return function;
}

// OpenImageIO's messages may span lines; the CLI prints one.
std::string oneLine(std::string message) {
  while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
  std::replace(message.begin(), message.end(), '\n', ' ');
  return message;
}

// Writes through `write(path, error, errorSize)` to a temporary name beside `file`, then renames.
template <typename Write>
void writeWhole(const std::filesystem::path& file, const Write& write) {
  // Same folder (so the rename is atomic) and same extension (OpenImageIO picks the format by it).
  std::string name(1, '.');  // appended piece by piece: GCC 12 warns falsely on "." + string
  name.append(file.stem().string()).append(".partial-").append(std::to_string(getpid()));
  name.append(file.extension().string());
  const std::filesystem::path temporary = file.parent_path() / name;
  const auto fail = [&](const std::string& why) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw std::runtime_error(file.string() + ": cannot write image: " + oneLine(why));
  };
  char error[512] = {};
  if (!write(temporary.c_str(), error, sizeof error)) fail(error);
  std::error_code renameError;
  std::filesystem::rename(temporary, file, renameError);
  if (renameError) fail(renameError.message());
}

void requirePixels(const std::filesystem::path& file, std::uint32_t width, std::uint32_t height, int channels,
                   std::size_t given) {
  if (channels <= 0 || given != std::size_t(width) * height * std::size_t(channels))
    throw std::invalid_argument(file.string() + ": cannot write image: " + std::to_string(given) + " values for " +
                                std::to_string(width) + "x" + std::to_string(height) + "x" + std::to_string(channels));
}

}  // namespace

ImagePluginPreload::ImagePluginPreload()
    : loading_([] {
        try {
          imageLibrary();
        } catch (const std::exception&) {  // reported again, with its reason, where an image is read or written
        }
      }) {}

bool writesWithoutPlugin(const std::filesystem::path& file) { return file.extension() == ".png"; }

void writeImage8(const std::filesystem::path& file, std::uint32_t width, std::uint32_t height, int channels,
                 std::span<const std::uint8_t> pixels) {
  requirePixels(file, width, height, channels, pixels.size());
  const auto write =
      writesWithoutPlugin(file) && channels <= 4 ? &writePng8 : imageFunction<PbsWriteImage8>("pbs_write_image8");
  writeWhole(file, [&](const char* path, char* error, std::size_t errorSize) {
    return write(path, width, height, channels, pixels.data(), error, errorSize);
  });
}

void writeImageFloat(const std::filesystem::path& file, std::uint32_t width, std::uint32_t height, int channels,
                     std::span<const float> pixels) {
  requirePixels(file, width, height, channels, pixels.size());
  const auto write = imageFunction<PbsWriteImageFloat>("pbs_write_image_float");
  writeWhole(file, [&](const char* path, char* error, std::size_t errorSize) {
    return write(path, width, height, channels, pixels.data(), error, errorSize);
  });
}

RgbaImage readImage(const std::filesystem::path& file) {
  const auto fail = [&](const std::string& why) { throw InputError(file.string(), "cannot read image", oneLine(why)); };
  std::error_code status;
  if (!std::filesystem::is_regular_file(file, status))
    fail(std::filesystem::exists(file, status) ? "not a file" : "no such file");
  const auto readSize = imageFunction<PbsReadImageSize>("pbs_read_image_size");
  const auto read = imageFunction<PbsReadImage>("pbs_read_image");
  char error[512] = {};
  RgbaImage image;
  if (!readSize(file.c_str(), &image.width, &image.height, error, sizeof error)) fail(error);
  image.pixels.resize(image.pixelCount());
  static_assert(sizeof(glm::vec4) == 4 * sizeof(float), "RgbaImage pixels must be packed float RGBA");
  if (!read(file.c_str(), image.width, image.height, &image.pixels.data()->x, error, sizeof error)) fail(error);
  return image;
}

}  // namespace pbs::cli
