/* The C interface of the image plug-in (libpbs_image_io.so), looked up by name with dlsym. No memory
   crosses the boundary: the caller owns every buffer, and asks for an image's size before reading it. */
#pragma once

#include <cstddef>
#include <cstdint>

extern "C" {

/* Every function returns 1 on success; 0 with a message in `error` (NUL-terminated, at most errorSize
   bytes) on failure. Rows run top first; the file name's extension names the format. Colour is
   written and read as stored: straight, never multiplied or divided by alpha. */

/* Writes width×height pixels of `channels` 8-bit values. */
int pbs_write_image8(const char* path, std::uint32_t width, std::uint32_t height, int channels,
                     const std::uint8_t* pixels, char* error, std::size_t errorSize);

/* Writes width×height pixels of `channels` float values: stored as 32-bit float where the format
   has it (EXR, TIFF), else converted by OpenImageIO to the format's nearest type (PNG: 8 bits, clamped). */
int pbs_write_image_float(const char* path, std::uint32_t width, std::uint32_t height, int channels,
                          const float* pixels, char* error, std::size_t errorSize);

/* The size of the first subimage of any file OpenImageIO reads: what pbs_read_image needs. */
int pbs_read_image_size(const char* path, std::uint32_t* width, std::uint32_t* height, char* error,
                        std::size_t errorSize);

/* Reads that subimage as width×height float RGBA (the size pbs_read_image_size gave; another fails)
   into `rgba` (4·width·height floats). Integer formats map to 0..1, floats stay as stored; grey
   becomes R = G = B; a file without alpha gets alpha 1. */
int pbs_read_image(const char* path, std::uint32_t width, std::uint32_t height, float* rgba, char* error,
                   std::size_t errorSize);

using PbsWriteImage8 = decltype(&pbs_write_image8);
using PbsWriteImageFloat = decltype(&pbs_write_image_float);
using PbsReadImageSize = decltype(&pbs_read_image_size);
using PbsReadImage = decltype(&pbs_read_image);
}
