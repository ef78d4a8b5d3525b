// The one shading of every render mode (exact, embree, surfels), so their images compare pixel for
// pixel: base colour × (ambient + (1 − ambient) · |n · v|) with v the camera's viewing direction.
#pragma once

#include "pbs/raster/camera.hpp"
#include "pbs/raster/framebuffer.hpp"
#include "pbs/raster/supersampling.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace pbs {

inline constexpr float kHeadlightAmbient = 0.3f;

// One linear RGBA value in [0, 1] per pixel, rows top first: the shaded colour with alpha 1 where the
// G-buffer is covered (its coverage where it has the coverage channel), (0, 0, 0, 0) elsewhere. |n · v| makes surfaces
// two-sided (capture and the ray caster do not cull back faces either). Needs the colour and normal channels; throws
// std::invalid_argument otherwise. A zero normal (a degenerate surface) shades as facing the camera.
std::vector<glm::vec4> shadeHeadlight(const Framebuffer& gbuffer, const Camera& camera);

// Adds the shaded colours of the G-buffer's covered pixels to `sums` (sized to the G-buffer, else
// std::invalid_argument) and counts one more sample: one supersampling pass (supersampling.hpp).
void accumulateHeadlight(const Framebuffer& gbuffer, const Camera& camera, SampleSums& sums);

// The same as RGBA8 (rounded to nearest), for PNG output.
std::vector<std::uint8_t> toRgba8(const std::vector<glm::vec4>& image);
// One channel of it (the definition; toRgba8 of a pixel rounds four at once): clamped to [0, 1] (NaN as 0),
// rounded to nearest with halves away from zero, as
// std::lround rounds: the float product plus one half is exact in double, so truncating it is the rounding,
// without a call per channel.
inline std::uint8_t toByte(float channel) {
  const float clamped = channel > 0.0f ? (channel < 1.0f ? channel : 1.0f) : 0.0f;
  return std::uint8_t(std::int32_t(double(clamped * 255.0f) + 0.5));
}
// One pixel of it: toByte of each channel, the four at once in vector lanes (no branch, one conversion each
// way), since frames bound for 8-bit files convert every pixel.
[[gnu::always_inline]] inline glm::u8vec4 toRgba8(const glm::vec4& pixel) {
  typedef float Floats __attribute__((vector_size(16)));
  typedef double Doubles __attribute__((vector_size(32)));
  typedef std::int32_t Ints __attribute__((vector_size(16)));
  const Floats channels = {pixel.r, pixel.g, pixel.b, pixel.a};
  const Floats zero = {}, one = zero + 1.0f;
  const Floats clamped = channels > zero ? (channels < one ? channels : one) : zero;
  const Ints bytes = __builtin_convertvector(__builtin_convertvector(clamped * 255.0f, Doubles) + 0.5, Ints);
  return {std::uint8_t(bytes[0]), std::uint8_t(bytes[1]), std::uint8_t(bytes[2]), std::uint8_t(bytes[3])};
}

// toRgba8(shadeHeadlight(gbuffer, camera)), bit for bit, in one pass: a frame bound for an 8-bit file never
// holds its float image (16 bytes a pixel written, then read again to convert).
std::vector<std::uint8_t> shadeHeadlightRgba8(const Framebuffer& gbuffer, const Camera& camera);

}  // namespace pbs
