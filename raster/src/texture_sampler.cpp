// Base colours: wrap modes, nearest and bilinear filtering over RGBA8 texels, RGBA8 rounding.
#include "pbs/raster/texture.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace pbs {
namespace {

std::int64_t positiveModulo(std::int64_t i, std::int64_t n) {
  const std::int64_t m = i % n;
  return m < 0 ? m + n : m;
}

std::int64_t wrapTexel(std::int64_t i, std::int64_t size, TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::ClampToEdge: return std::clamp<std::int64_t>(i, 0, size - 1);
    case TextureWrap::MirroredRepeat: {
      const std::int64_t m = positiveModulo(i, 2 * size);
      return m < size ? m : 2 * size - 1 - m;
    }
    case TextureWrap::Repeat: break;
  }
  return positiveModulo(i, size);
}

// The coordinate in texels, bounded so that its floor converts to an integer (floats that large
// have no fraction left anyway); NaN samples the origin.
float texelCoordinate(float t, std::uint32_t size) {
  const float s = t * float(size);
  constexpr float kLimit = 0x1p40f;
  return s == s ? std::clamp(s, -kLimit, kLimit) : 0.0f;
}

glm::vec4 texel(const Texture& texture, std::int64_t x, std::int64_t y) {
  const std::uint8_t* p = texture.rgba8.data() + (std::size_t(y) * texture.width + std::size_t(x)) * 4;
  return {p[0], p[1], p[2], p[3]};
}

}  // namespace

glm::u8vec4 toUnorm8(const glm::vec4& color) {
  const auto unorm8 = [](float v) {
    const float clamped = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
    return std::uint8_t(clamped * 255.0f + 0.5f);
  };
  return {unorm8(color.r), unorm8(color.g), unorm8(color.b), unorm8(color.a)};
}

bool isSampleable(const Texture& texture) {
  return texture.width > 0 && texture.height > 0 &&
         texture.rgba8.size() >= std::size_t(texture.width) * texture.height * 4;
}

glm::vec4 sampleTexture(const Texture& texture, glm::vec2 uv) {
  const std::int64_t w = texture.width, h = texture.height;
  const float s = texelCoordinate(uv.x, texture.width), t = texelCoordinate(uv.y, texture.height);
  if (texture.magFilter == TextureFilter::Nearest) {
    const std::int64_t x = wrapTexel(std::int64_t(std::floor(s)), w, texture.wrapS);
    const std::int64_t y = wrapTexel(std::int64_t(std::floor(t)), h, texture.wrapT);
    return texel(texture, x, y) / 255.0f;
  }
  const float fs = std::floor(s - 0.5f), ft = std::floor(t - 0.5f);
  const float ax = s - 0.5f - fs, ay = t - 0.5f - ft;
  const std::int64_t x0 = wrapTexel(std::int64_t(fs), w, texture.wrapS);
  const std::int64_t x1 = wrapTexel(std::int64_t(fs) + 1, w, texture.wrapS);
  const std::int64_t y0 = wrapTexel(std::int64_t(ft), h, texture.wrapT);
  const std::int64_t y1 = wrapTexel(std::int64_t(ft) + 1, h, texture.wrapT);
  const glm::vec4 top = glm::mix(texel(texture, x0, y0), texel(texture, x1, y0), ax);
  const glm::vec4 bottom = glm::mix(texel(texture, x0, y1), texel(texture, x1, y1), ax);
  return glm::mix(top, bottom, ay) / 255.0f;
}

}  // namespace pbs
