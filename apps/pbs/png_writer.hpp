// 8-bit PNG written with libpng, in the process: the one image format a render writes by default does
// not need the OpenImageIO plug-in, whose loading (260 libraries, 0.3-0.4 s) would be a third of a
// large scene's first frame.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pbs::cli {

// Writes width×height pixels of `channels` (1 grey, 2 grey+alpha, 3 RGB, 4 RGBA) 8-bit values, rows top
// first, to `path`. Returns 1, or 0 with the reason in `error` (errorSize bytes): the plug-in's
// pbs_write_image8, so that either can be called.
int writePng8(const char* path, std::uint32_t width, std::uint32_t height, int channels, const std::uint8_t* pixels,
              char* error, std::size_t errorSize);

// The same PNG file's bytes, in memory (for `pbs view`). Throws std::runtime_error with libpng's reason.
std::vector<std::uint8_t> encodePng8(std::uint32_t width, std::uint32_t height, int channels,
                                     const std::uint8_t* pixels);

}  // namespace pbs::cli
