// Writing and reading images (PNG, EXR, … by extension, through the OpenImageIO plug-in), whole or not
// at all.
#pragma once

#include <pbs/raster/image_metrics.hpp>

#include <cstdint>
#include <filesystem>
#include <span>
#include <thread>

namespace pbs::cli {

// Loading the image plug-in maps OpenImageIO and the 260 libraries it depends on: 0.3-0.4 s, a third of
// a large scene's first frame. A command that will write an image makes one of these first, so that the
// loading runs on a thread of its own while the command reads its scene; destroying it waits for the
// thread. A failure to load is left for the first image call, which reports it.
class ImagePluginPreload {
 public:
  ImagePluginPreload();

 private:
  std::jthread loading_;
};

// Whether writeImage8 writes `file` without the plug-in: a .png (1 to 4 channels), by libpng.
bool writesWithoutPlugin(const std::filesystem::path& file);

// Writes width×height pixels of `channels` 8-bit values each, rows top first, to a temporary name
// beside `file` and renames it into place. Throws std::runtime_error naming the file on failure.
void writeImage8(const std::filesystem::path& file, std::uint32_t width, std::uint32_t height, int channels,
                 std::span<const std::uint8_t> pixels);

// The same with float values (linear): 32-bit float in EXR (and other float formats), converted to
// the format's own type elsewhere (PNG: 8 bits, clamped to 0..1).
void writeImageFloat(const std::filesystem::path& file, std::uint32_t width, std::uint32_t height, int channels,
                     std::span<const float> pixels);

// Reads any image OpenImageIO reads as float RGBA: integer formats scaled to 0..1, float formats as
// stored, grey copied to R, G and B, alpha 1 where the file has none, colour never multiplied by
// alpha (pbs writes straight colour too). Throws pbs::InputError
// ("FILE: cannot read image: WHY") on failure.
RgbaImage readImage(const std::filesystem::path& file);

}  // namespace pbs::cli
