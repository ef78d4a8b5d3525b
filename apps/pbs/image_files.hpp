// Writing images (PNG, EXR, … by extension, through OpenImageIO), whole or not at all.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>

namespace pbs::cli {

// Writes width×height pixels of `channels` 8-bit values each, rows top first, to a temporary name
// beside `file` and renames it into place. Throws std::runtime_error naming the file on failure.
void writeImage8(const std::filesystem::path& file, std::uint32_t width, std::uint32_t height, int channels,
                 std::span<const std::uint8_t> pixels);

}  // namespace pbs::cli
