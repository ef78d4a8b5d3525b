// A shaded image drawn at a lower resolution brought up to the frame's: what a frame-time budget does when
// no cut of the scene fits it at full resolution (lod_budget.hpp).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace pbs {

// Input row y of a width-pixel image for the upscale: a pointer to its straight-RGBA pixels, either into an
// image held whole or into `scratch` (width pixels) after filling it. Called about once per input row and
// output task, from several threads at once.
using UpscaleRows = std::function<const glm::vec4*(std::uint32_t y, glm::vec4* scratch)>;

// Bilinear interpolation of a straight-RGBA image of width × height into one of toWidth × toHeight, pixel
// centres mapped onto each other (the image's edges clamp): colours are interpolated premultiplied by alpha,
// so a covered pixel's colour does not bleed toward the empty (0, 0, 0, 0) pixels around it, and alpha
// ramps over the edge. Deterministic (an output pixel's arithmetic does not depend on which task computes it).
// Throws std::invalid_argument when the image is not width × height or a size is 0.
std::vector<glm::vec4> upscaleBilinear(std::span<const glm::vec4> image, std::uint32_t width, std::uint32_t height,
                                       std::uint32_t toWidth, std::uint32_t toHeight);
// The same with the input made a row at a time (a budget's G-buffer shaded as it is upscaled, never held
// whole); bit for bit upscaleBilinear of the image those rows make.
std::vector<glm::vec4> upscaleBilinear(const UpscaleRows& rows, std::uint32_t width, std::uint32_t height,
                                       std::uint32_t toWidth, std::uint32_t toHeight);

// toRgba8(upscaleBilinear(…)) bit for bit, in one pass: a frame bound for an 8-bit file never holds its
// full-size float image.
std::vector<std::uint8_t> upscaleBilinearRgba8(std::span<const glm::vec4> image, std::uint32_t width,
                                               std::uint32_t height, std::uint32_t toWidth, std::uint32_t toHeight);
std::vector<std::uint8_t> upscaleBilinearRgba8(const UpscaleRows& rows, std::uint32_t width, std::uint32_t height,
                                               std::uint32_t toWidth, std::uint32_t toHeight);

}  // namespace pbs
