// The texture filters themselves (wrap modes, nearest and bilinear texels, mip levels, the level a footprint picks),
// inline so that a caller cloned for AVX2 (the rasterizer's resolve) samples without a call: texture_sampler.cpp's
// entry points and the resolve share this one copy.
#pragma once

#include "pbs/raster/simd_clones.hpp"
#include "pbs/raster/texture.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace pbs::texture_filters {

PBS_CLONE_INLINE std::int64_t positiveModulo(std::int64_t i, std::int64_t n) {
  // Most coordinates lie in [0, 1): no division for them (one is 20-40 cycles).
  if (std::uint64_t(i) < std::uint64_t(n)) return i;
  const std::int64_t m = i % n;
  return m < 0 ? m + n : m;
}

PBS_CLONE_INLINE std::int64_t wrapTexel(std::int64_t i, std::int64_t size, TextureWrap wrap) {
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
PBS_CLONE_INLINE float texelCoordinate(float t, std::uint32_t size) {
  const float s = t * float(size);
  constexpr float kLimit = 0x1p40f;
  return s == s ? std::clamp(s, -kLimit, kLimit) : 0.0f;
}

// One level's texels as the filters read them.
struct Level {
  std::int64_t width, height;
  const std::uint8_t* rgba8;
};

// RGBA in four float lanes: a texel's bytes widen in one vector conversion instead of four scalar ones,
// and the filters' arithmetic runs on all four channels at once. Every lane sees the operations glm's
// vec4 would apply to its component, in the same order, so the colours keep their bits.
typedef float Rgba __attribute__((vector_size(4 * sizeof(float))));
typedef std::int32_t Rgba32 __attribute__((vector_size(4 * sizeof(std::int32_t))));

PBS_CLONE_INLINE Rgba texel(const Level& level, std::int64_t x, std::int64_t y) {
  std::uint32_t word;
  std::memcpy(&word, level.rgba8 + (std::size_t(y) * std::size_t(level.width) + std::size_t(x)) * 4, sizeof word);
  // The bytes in the lanes by shifts and a mask, which vectorise where a conversion from bytes does not.
  const Rgba32 bytes = (Rgba32{} + std::int32_t(word)) >> Rgba32{0, 8, 16, 24} & 0xff;
  return __builtin_convertvector(bytes, Rgba);
}

// glm::mix's x · (1 − a) + y · a.
PBS_CLONE_INLINE Rgba mix(const Rgba& x, const Rgba& y, float a) { return x * (1.0f - a) + y * a; }

// RGBA in [0, 255] at uv in one level, by nearest or bilinear filtering.
PBS_CLONE_INLINE Rgba sampleLevel(const Level& level, TextureFilter filter, const Texture& texture, glm::vec2 uv) {
  const std::int64_t w = level.width, h = level.height;
  const float s = texelCoordinate(uv.x, std::uint32_t(w)), t = texelCoordinate(uv.y, std::uint32_t(h));
  if (filter == TextureFilter::Nearest) {
    const std::int64_t x = wrapTexel(std::int64_t(std::floor(s)), w, texture.wrapS);
    const std::int64_t y = wrapTexel(std::int64_t(std::floor(t)), h, texture.wrapT);
    return texel(level, x, y);
  }
  const float fs = std::floor(s - 0.5f), ft = std::floor(t - 0.5f);
  const float ax = s - 0.5f - fs, ay = t - 0.5f - ft;
  const std::int64_t x0 = wrapTexel(std::int64_t(fs), w, texture.wrapS);
  const std::int64_t x1 = wrapTexel(std::int64_t(fs) + 1, w, texture.wrapS);
  const std::int64_t y0 = wrapTexel(std::int64_t(ft), h, texture.wrapT);
  const std::int64_t y1 = wrapTexel(std::int64_t(ft) + 1, h, texture.wrapT);
  const Rgba top = mix(texel(level, x0, y0), texel(level, x1, y0), ax);
  const Rgba bottom = mix(texel(level, x0, y1), texel(level, x1, y1), ax);
  return mix(top, bottom, ay);
}

PBS_CLONE_INLINE Level levelOf(const Texture& texture, std::size_t index) {
  if (index == 0) return {texture.width, texture.height, texture.rgba8.data()};
  const TextureLevel& level = texture.mipLevels[index - 1];
  return {level.width, level.height, level.rgba8.data()};
}

// The squared lengths of a footprint's two sides (dx, dy) in level-0 texels.
PBS_CLONE_INLINE glm::vec2 squaredSides(const Texture& texture, const TextureFootprint& f) {
  const glm::vec2 size(float(texture.width), float(texture.height));
  const glm::vec2 x = f.dx * size, y = f.dy * size;
  return {glm::dot(x, x), glm::dot(y, y)};
}

// log2 of a footprint's larger side, from its squared sides: NaN where it has none (zero or NaN), which
// samples level 0 magnified; an infinite one (a triangle seen edge-on) picks the last level.
PBS_CLONE_INLINE float levelOfDetail(const glm::vec2& sides2) {
  const float rho2 = std::max(sides2.x, sides2.y);
  return rho2 > 0.0f ? 0.5f * std::log2(std::min(rho2, 1e30f)) : std::numeric_limits<float>::quiet_NaN();
}

// One probe at level of detail `lod`: level 0 magnified, else the level or levels `mipmap` picks; RGBA in
// [0, 1].
PBS_CLONE_INLINE Rgba sampleProbe(const Texture& texture, glm::vec2 uv, float lod) {
  // Not greater than 0 (NaN included): magnified.
  if (!(lod > 0.0f)) return sampleLevel(levelOf(texture, 0), texture.magFilter, texture, uv) / 255.0f;
  const std::size_t last = texture.mipLevels.size();
  switch (texture.mipmap) {
    case TextureMipmap::None: break;
    case TextureMipmap::Nearest: {
      // OpenGL's nearest level: ⌈λ + ½⌉ − 1, at most the last.
      const auto level = std::size_t(std::min(std::ceil(lod + 0.5f) - 1.0f, float(last)));
      return sampleLevel(levelOf(texture, level), texture.minFilter, texture, uv) / 255.0f;
    }
    case TextureMipmap::Linear: {
      if (!(lod < float(last))) return sampleLevel(levelOf(texture, last), texture.minFilter, texture, uv) / 255.0f;
      const auto level = std::size_t(lod);
      const Rgba fine = sampleLevel(levelOf(texture, level), texture.minFilter, texture, uv);
      const Rgba coarse = sampleLevel(levelOf(texture, level + 1), texture.minFilter, texture, uv);
      return mix(fine, coarse, lod - float(level)) / 255.0f;
    }
  }
  return sampleLevel(levelOf(texture, 0), texture.minFilter, texture, uv) / 255.0f;
}

PBS_CLONE_INLINE glm::vec4 toVec4(const Rgba& lanes) { return {lanes[0], lanes[1], lanes[2], lanes[3]}; }

// sampleTextureAtLevel, inline.
PBS_CLONE_INLINE glm::vec4 sampleAtLevel(const Texture& texture, glm::vec2 uv, float lod) {
  return toVec4(sampleProbe(texture, uv, lod));
}

}  // namespace pbs::texture_filters
