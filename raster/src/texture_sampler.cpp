// Base colours: wrap modes, nearest and bilinear filtering over RGBA8 texels, mip chains and the level a
// footprint picks, RGBA8 rounding.
#include "pbs/raster/texture.hpp"

#include "pbs/raster/simd_clones.hpp"
#include "texture_filters.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace pbs {

using namespace texture_filters;

bool isSampleable(const Texture& texture) {
  return texture.width > 0 && texture.height > 0 &&
         texture.rgba8.size() >= std::size_t(texture.width) * texture.height * 4;
}

void buildMipLevels(Texture& texture) {
  texture.mipLevels.clear();
  if (texture.mipmap == TextureMipmap::None || !isSampleable(texture)) return;
  Level previous = levelOf(texture, 0);
  while (previous.width > 1 || previous.height > 1) {
    TextureLevel next;
    next.width = std::uint32_t(std::max<std::int64_t>(1, previous.width / 2));
    next.height = std::uint32_t(std::max<std::int64_t>(1, previous.height / 2));
    next.rgba8.resize(std::size_t(next.width) * next.height * 4);
    for (std::int64_t y = 0; y < next.height; ++y)
      for (std::int64_t x = 0; x < next.width; ++x) {
        const std::int64_t xs[2] = {2 * x, std::min(2 * x + 1, previous.width - 1)};
        const std::int64_t ys[2] = {2 * y, std::min(2 * y + 1, previous.height - 1)};
        for (int c = 0; c < 4; ++c) {
          unsigned sum = 2;  // rounds the mean to nearest
          for (std::int64_t sy : ys)
            for (std::int64_t sx : xs)
              sum += previous.rgba8[(std::size_t(sy) * std::size_t(previous.width) + std::size_t(sx)) * 4 + c];
          next.rgba8[(std::size_t(y) * next.width + std::size_t(x)) * 4 + c] = std::uint8_t(sum / 4);
        }
      }
    texture.mipLevels.push_back(std::move(next));
    previous = levelOf(texture, texture.mipLevels.size());
  }
}

// Cloned (with its helpers inlined) since both the rasterizer's resolve and the ray caster's shading
// spend a textured frame's time here.
PBS_AVX2_CLONES
glm::vec4 sampleTexture(const Texture& texture, glm::vec2 uv, const TextureFootprint& footprint) {
  if (footprint.maxProbes == 0) return toVec4(sampleProbe(texture, uv, std::numeric_limits<float>::quiet_NaN()));
  // A footprint longer than wide (a surface seen at a slant) is covered by probes spaced along its long
  // side, each with the footprint's long side divided among them: the level follows the short side, so the
  // texture is not blurred across the slant as one probe sized by the long side would blur it.
  const glm::vec2 sides2 = squaredSides(texture, footprint);
  // One probe at most (a capture's, or isotropic filtering): the level alone, without the sides' lengths.
  if (footprint.maxProbes == 1) return sampleTextureAtLevel(texture, uv, levelOfDetail(sides2));
  const float lengthX = std::sqrt(sides2.x), lengthY = std::sqrt(sides2.y);
  const float longSide = std::max(lengthX, lengthY), shortSide = std::min(lengthX, lengthY);
  const float probes = shortSide > 0.0f && longSide < 1e30f && longSide > 1.0f
                           ? std::min(std::round(longSide / shortSide), float(footprint.maxProbes))
                           : 1.0f;
  if (!(probes > 1.0f)) return toVec4(sampleProbe(texture, uv, levelOfDetail(sides2)));
  const bool alongX = lengthX >= lengthY;
  const glm::vec2 axis = alongX ? footprint.dx : footprint.dy;
  const TextureFootprint probe = alongX ? TextureFootprint{footprint.dx / probes, footprint.dy, 1}
                                        : TextureFootprint{footprint.dx, footprint.dy / probes, 1};
  const float lod = levelOfDetail(squaredSides(texture, probe));  // every probe's footprint is the same
  const int count = int(probes);
  Rgba sum{};
  for (int i = 0; i < count; ++i) sum += sampleProbe(texture, uv + axis * ((float(i) + 0.5f) / probes - 0.5f), lod);
  return toVec4(sum / probes);
}

float textureLevelOfDetail(const Texture& texture, const TextureFootprint& footprint) {
  return levelOfDetail(squaredSides(texture, footprint));
}

PBS_AVX2_CLONES
glm::vec4 sampleTextureAtLevel(const Texture& texture, glm::vec2 uv, float lod) {
  return sampleAtLevel(texture, uv, lod);
}

}  // namespace pbs
