// The one shading of every render mode (exact, embree, surfels), so their images compare pixel for
// pixel: base colour × (ambient + (1 − ambient) · |n · v|) with v the camera's viewing direction.
#pragma once

#include "pbs/raster/camera.hpp"
#include "pbs/raster/framebuffer.hpp"
#include "pbs/raster/supersampling.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <cstring>
#include <vector>

namespace pbs {

inline constexpr float kHeadlightAmbient = 0.3f;

// v: the camera's viewing direction in world space (its eye −Z), the same at every pixel. Passes that blend
// normals before shading turn them to one side of it, since shading reads |n · v| and their signs are arbitrary.
glm::vec3 headlightDirection(const Camera& camera);

// One linear RGBA value in [0, 1] per pixel, rows top first: the shaded colour with alpha 1 where the
// G-buffer is covered (its coverage where it has the coverage channel), (0, 0, 0, 0) elsewhere. |n · v| makes surfaces
// two-sided (capture and the ray caster do not cull back faces either). Needs the colour and normal channels; throws
// std::invalid_argument otherwise. A zero normal (a degenerate surface) shades as facing the camera.
std::vector<glm::vec4> shadeHeadlight(const Framebuffer& gbuffer, const Camera& camera);

// The same a pixel or a row at a time, for passes that shade as they go (a budget's lower resolution is
// shaded as it is upscaled). Throws std::invalid_argument as shadeHeadlight does.
class HeadlightShader {
 public:
  HeadlightShader(const Framebuffer& gbuffer, const Camera& camera);
  // A covered pixel's colour, alpha its coverage (1 without the coverage channel).
  glm::vec4 shade(std::size_t pixel) const;
  // Row y into out[0 … width): shadeHeadlight's pixels, bit for bit.
  void shadeRow(std::uint32_t y, glm::vec4* out) const;

 private:
  const Framebuffer& gbuffer_;
  glm::vec3 view_;
  bool partial_;
};

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
// toByte of every lane of a GCC vector of floats (4: a pixel; 8: two) into the low byte of each lane of
// `bytes` (ints in [0, 255]), with no branch and no double (by reference: a 256-bit vector passed by value
// would depend on the caller's instruction set): the product p in [0, 255] splits exactly into its whole part w and
// fraction p − w (Sterbenz: w ≥ p / 2 once p ≥ 1), so w + (fraction ≥ 1/2) is toByte's rounding, which p + 1/2 in float
// would not be (0.49999997 + 0.5 rounds up to 1).
template <class Floats, class Ints>
[[gnu::always_inline]] inline void roundToBytes(const Floats& channels, Ints& bytes) {
  static_assert(sizeof(Floats) == sizeof(Ints));
  const Floats zero = {}, one = zero + 1.0f;
  const Floats product = (channels > zero ? (channels < one ? channels : one) : zero) * 255.0f;
  const Ints whole = __builtin_convertvector(product, Ints);
  bytes = whole - (product - __builtin_convertvector(whole, Floats) >= 0.5f);  // true is −1 in each lane
}

// One pixel of it, the four channels at once in vector lanes, since frames bound for 8-bit files convert
// every pixel.
[[gnu::always_inline]] inline glm::u8vec4 toRgba8(const glm::vec4& pixel) {
  typedef float Floats __attribute__((vector_size(16)));
  typedef std::int32_t Ints __attribute__((vector_size(16)));
  typedef std::uint8_t Bytes __attribute__((vector_size(16)));
  Ints rounded;
  roundToBytes(Floats{pixel.r, pixel.g, pixel.b, pixel.a}, rounded);
  const Bytes lanes = Bytes(rounded);
  // Each lane's low byte, by one shuffle (a conversion to bytes would extract lane by lane).
  const auto bytes = __builtin_shufflevector(lanes, lanes, 0, 4, 8, 12);
  glm::u8vec4 result;
  std::memcpy(&result, &bytes, sizeof result);
  return result;
}

// toRgba8(shadeHeadlight(gbuffer, camera)), bit for bit, in one pass: a frame bound for an 8-bit file never
// holds its float image (16 bytes a pixel written, then read again to convert).
std::vector<std::uint8_t> shadeHeadlightRgba8(const Framebuffer& gbuffer, const Camera& camera);

}  // namespace pbs
