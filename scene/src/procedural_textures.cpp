// Procedural textures for the generated plant, built from wrapping value noise so they tile.
#include "procedural_textures.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace pbs {
namespace {

constexpr std::uint32_t kSize = 256;

// An integer hash (lowbias32 by Chris Wellons) of a lattice point: same everywhere, no tables.
std::uint32_t hash(std::uint32_t x, std::uint32_t y, std::uint32_t seed) {
  std::uint32_t h = x * 0x8DA6B343u ^ y * 0xD8163841u ^ seed * 0xCB1AB31Fu;
  h ^= h >> 16;
  h *= 0x7FEB352Du;
  h ^= h >> 15;
  h *= 0x846CA68Bu;
  h ^= h >> 16;
  return h;
}

float hashUnit(std::uint32_t x, std::uint32_t y, std::uint32_t seed) {
  return float(hash(x, y, seed) >> 8) * 0x1.0p-24f;
}

// Value noise in 0..1 on a lattice of `cells` × `cells` over the unit square that wraps at its
// edges, so a texture built from it repeats without a seam.
float tilingNoise(float u, float v, std::uint32_t cells, std::uint32_t seed) {
  const float x = u * float(cells), y = v * float(cells);
  const float fx = std::floor(x), fy = std::floor(y);
  const auto ix = std::uint32_t(fx) % cells, iy = std::uint32_t(fy) % cells;
  const auto jx = (ix + 1) % cells, jy = (iy + 1) % cells;
  const auto smooth = [](float t) { return t * t * (3.0f - 2.0f * t); };
  const float tx = smooth(x - fx), ty = smooth(y - fy);
  const float bottom = std::lerp(hashUnit(ix, iy, seed), hashUnit(jx, iy, seed), tx);
  const float top = std::lerp(hashUnit(ix, jy, seed), hashUnit(jx, jy, seed), tx);
  return std::lerp(bottom, top, ty);
}

// Octaves of tilingNoise, each twice as fine and half as strong, normalised to 0..1.
float fractalNoise(float u, float v, std::uint32_t cells, std::uint32_t octaves, std::uint32_t seed) {
  float sum = 0.0f, amplitude = 1.0f, total = 0.0f;
  for (std::uint32_t o = 0; o < octaves; ++o, cells *= 2, amplitude *= 0.5f) {
    sum += amplitude * tilingNoise(u, v, cells, seed + o);
    total += amplitude;
  }
  return sum / total;
}

float smoothstep(float edge0, float edge1, float x) {
  const float t = std::clamp((x - edge0) / (edge1 - edge0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

// A texture whose sRGB colour at pixel centre (u, v) is colourAt(u, v, x, y).
template <typename ColourAt>
Texture paintTexture(std::string name, ColourAt colourAt) {
  Texture texture;
  texture.name = std::move(name);
  texture.width = texture.height = kSize;
  texture.rgba8.resize(std::size_t(kSize) * kSize * 4);
  for (std::uint32_t y = 0; y < kSize; ++y) {
    for (std::uint32_t x = 0; x < kSize; ++x) {
      const glm::vec3 colour = colourAt((float(x) + 0.5f) / kSize, (float(y) + 0.5f) / kSize, x, y);
      std::uint8_t* pixel = &texture.rgba8[(std::size_t(y) * kSize + x) * 4];
      for (int c = 0; c < 3; ++c) pixel[c] = std::uint8_t(std::lround(std::clamp(colour[c], 0.0f, 1.0f) * 255.0f));
      pixel[3] = 255;
    }
  }
  return texture;
}

}  // namespace

Texture makePaintedSteelTexture(std::string name, glm::vec3 paint, glm::vec3 stripe, std::uint32_t seed) {
  return paintTexture(std::move(name), [&](float u, float v, std::uint32_t, std::uint32_t) {
    const float shade = 0.92f + 0.16f * fractalNoise(u, v, 4, 3, seed);
    glm::vec3 colour = (v > 0.42f && v < 0.58f ? stripe : paint) * shade;
    const float rust = smoothstep(0.68f, 0.76f, fractalNoise(u, v, 8, 4, seed + 101));
    const glm::vec3 rustColour =
        glm::mix(glm::vec3(0.42f, 0.2f, 0.08f), glm::vec3(0.25f, 0.12f, 0.05f), fractalNoise(u, v, 32, 2, seed + 202));
    return glm::mix(colour, rustColour, rust);
  });
}

Texture makeCheckerPlateTexture(std::string name, std::uint32_t seed) {
  constexpr std::uint32_t kLugs = 16;  // lugs across the tile
  return paintTexture(std::move(name), [&](float u, float v, std::uint32_t, std::uint32_t) {
    const float cu = u * kLugs, cv = v * kLugs;
    const float lu = 2.0f * (cu - std::floor(cu)) - 1.0f, lv = 2.0f * (cv - std::floor(cv)) - 1.0f;
    // Neighbouring lugs lean opposite ways, the classic diamond plate.
    const float lean = (std::uint32_t(cu) + std::uint32_t(cv)) % 2 == 0 ? 1.0f : -1.0f;
    const float along = (lu + lean * lv) * 0.7071f, across = (lu - lean * lv) * 0.7071f;
    const float lug = (along / 0.75f) * (along / 0.75f) + (across / 0.22f) * (across / 0.22f);
    float shade = 0.45f + 0.1f * fractalNoise(u, v, 8, 3, seed);
    if (lug < 1.0f) shade += 0.18f + 0.12f * across;
    return glm::vec3(shade * 0.95f, shade * 0.97f, shade);
  });
}

Texture makeHazardStripeTexture(std::string name, std::uint32_t seed) {
  return paintTexture(std::move(name), [&](float u, float v, std::uint32_t, std::uint32_t) {
    const float band = (u + v) * 8.0f;  // whole stripes across the tile in both directions
    const glm::vec3 paint = band - std::floor(band) < 0.5f ? glm::vec3(0.95f, 0.75f, 0.05f) : glm::vec3(0.08f);
    const float worn = smoothstep(0.62f, 0.7f, fractalNoise(u, v, 8, 4, seed));
    const float dirt = 0.85f + 0.15f * fractalNoise(u, v, 16, 2, seed + 1);
    return glm::mix(paint, glm::vec3(0.45f), worn) * dirt;
  });
}

Texture makeConcreteTexture(std::string name, std::uint32_t seed) {
  return paintTexture(std::move(name), [&](float u, float v, std::uint32_t x, std::uint32_t y) {
    float grey = 0.46f + 0.24f * fractalNoise(u, v, 8, 5, seed);
    if (hashUnit(x, y, seed + 7) > 0.96f) grey *= 0.8f;  // pores
    if (y % 64 == 0) grey *= 0.75f;                      // formwork joints
    return glm::vec3(grey, grey * 0.98f, grey * 0.94f);
  });
}

}  // namespace pbs
