// The texture sampler's mip chain and the level a footprint picks (glTF's minFilter modes).
#include "pbs/raster/texture.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace pbs {
namespace {

// A width × height texture whose texel (x, y) has red x·16 + y, green 255 − red, blue 7, alpha 255.
Texture gradient(std::uint32_t width, std::uint32_t height, TextureMipmap mipmap) {
  Texture texture;
  texture.width = width;
  texture.height = height;
  texture.rgba8.resize(std::size_t(width) * height * 4);
  for (std::uint32_t y = 0; y < height; ++y)
    for (std::uint32_t x = 0; x < width; ++x) {
      std::uint8_t* texel = texture.rgba8.data() + (std::size_t(y) * width + x) * 4;
      texel[0] = std::uint8_t(x * 16 + y);
      texel[1] = std::uint8_t(255 - texel[0]);
      texel[2] = 7;
      texel[3] = 255;
    }
  texture.mipmap = mipmap;
  buildMipLevels(texture);
  return texture;
}

glm::vec4 texelOf(const TextureLevel& level, std::uint32_t x, std::uint32_t y) {
  const std::uint8_t* p = level.rgba8.data() + (std::size_t(y) * level.width + x) * 4;
  return glm::vec4(p[0], p[1], p[2], p[3]) / 255.0f;
}

// A square footprint whose sides are 2^lod texels of a square texture of this size.
TextureFootprint footprintOf(float lod, std::uint32_t size) {
  const float side = std::exp2(lod) / float(size);
  return {glm::vec2(side, 0.0f), glm::vec2(0.0f, side)};
}

TEST(TextureMips, LevelsHalveDownToOneTexelAndAverageWithRounding) {
  const Texture texture = gradient(5, 3, TextureMipmap::Linear);
  ASSERT_EQ(texture.mipLevels.size(), 2u);
  EXPECT_EQ(texture.mipLevels[0].width, 2u);
  EXPECT_EQ(texture.mipLevels[0].height, 1u);
  EXPECT_EQ(texture.mipLevels[1].width, 1u);
  EXPECT_EQ(texture.mipLevels[1].height, 1u);
  // Level 1 texel (1, 0) covers texels (2…3, 0…1): reds 32, 33, 48, 49, mean 40.5, rounded up.
  EXPECT_EQ(texture.mipLevels[0].rgba8[4], 41);
  EXPECT_EQ(texture.mipLevels[0].rgba8[5], 255 - 40);  // greens 223, 222, 207, 206: 214.5 → 215
  EXPECT_EQ(texture.mipLevels[0].rgba8[6], 7);
  // Level 2 averages level 1's two texels (reds 9 and 41), its one row repeated: 25.
  EXPECT_EQ(texture.mipLevels[1].rgba8[0], 25);
  EXPECT_TRUE(gradient(4, 4, TextureMipmap::None).mipLevels.empty()) << "no levels where none are used";
  EXPECT_EQ(gradient(1, 1, TextureMipmap::Linear).mipLevels.size(), 0u);
}

TEST(TextureMips, TheFootprintPicksTheLevel) {
  const Texture texture = gradient(8, 8, TextureMipmap::Linear);
  ASSERT_EQ(texture.mipLevels.size(), 3u);
  const glm::vec2 uv(0.375f, 0.125f);  // the centre of level 1's texel (1, 0)
  // Magnified or no footprint: level 0, bilinear between texels (2…3, 0…1).
  const glm::vec4 level0 = sampleTexture(texture, uv);
  EXPECT_NEAR(level0.r * 255.0f, (32 + 33 + 48 + 49) / 4.0f, 1e-3f);
  EXPECT_EQ(sampleTexture(texture, uv, footprintOf(-1.0f, 8)), level0);
  EXPECT_EQ(sampleTexture(texture, uv, footprintOf(0.0f, 8)), level0) << "λ = 0 is still magnified";
  const TextureFootprint nan{glm::vec2(std::numeric_limits<float>::quiet_NaN()), glm::vec2(0.0f)};
  EXPECT_EQ(sampleTexture(texture, uv, nan), level0);
  // Two texels a pixel: level 1 exactly; three: between 1 and 2 at log2 3 − 1.
  EXPECT_EQ(sampleTexture(texture, uv, footprintOf(1.0f, 8)), texelOf(texture.mipLevels[0], 1, 0));
  const float t = std::log2(3.0f) - 1.0f;
  const glm::vec4 blended = sampleTexture(texture, uv, footprintOf(std::log2(3.0f), 8));
  const glm::vec4 level2 = sampleTexture(texture, uv, footprintOf(2.0f, 8));
  const glm::vec4 expected = glm::mix(texelOf(texture.mipLevels[0], 1, 0), level2, t);
  for (int c = 0; c < 4; ++c) EXPECT_NEAR(blended[c], expected[c], 1e-6f);
  // Beyond the last level, and a footprint of infinite size (a triangle seen edge-on): the 1 × 1 level.
  const glm::vec4 last = texelOf(texture.mipLevels[2], 0, 0);
  EXPECT_EQ(sampleTexture(texture, uv, footprintOf(7.0f, 8)), last);
  const TextureFootprint infinite{glm::vec2(std::numeric_limits<float>::infinity(), 0.0f), glm::vec2(0.0f)};
  EXPECT_EQ(sampleTexture(texture, uv, infinite), last);
  // No probe at all (`--texture-filter none`): level 0 whatever the footprint.
  for (float lod : {1.0f, 3.0f, 7.0f}) {
    TextureFootprint unused = footprintOf(lod, 8);
    unused.maxProbes = 0;
    EXPECT_EQ(sampleTexture(texture, uv, unused), level0) << lod;
  }
}

// The split the resolve makes for affine triangles (the level found once per triangle) is sampleTexture to the bit:
// magnified, between levels, beyond the last, slanted, with no side and with NaN, for each mip mode.
TEST(TextureMips, ALevelFoundOnceSamplesAsTheOneProbeFootprintDoes) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (TextureMipmap mipmap : {TextureMipmap::None, TextureMipmap::Nearest, TextureMipmap::Linear}) {
    const Texture texture = gradient(16, 8, mipmap);
    const TextureFootprint footprints[] = {footprintOf(-1.0f, 16),
                                           footprintOf(0.3f, 16),
                                           footprintOf(1.7f, 16),
                                           footprintOf(9.0f, 16),
                                           {glm::vec2(0.3f, 0.05f), glm::vec2(-0.01f, 0.02f)},
                                           {},
                                           {glm::vec2(nan, 0.0f), glm::vec2(0.0f, 0.1f)}};
    for (const TextureFootprint& f : footprints)
      for (const glm::vec2 uv : {glm::vec2(0.1f, 0.2f), glm::vec2(0.77f, -1.3f), glm::vec2(5.5f, 0.5f)}) {
        const TextureFootprint one{f.dx, f.dy, 1};
        const glm::vec4 whole = sampleTexture(texture, uv, one);
        const glm::vec4 split = sampleTextureAtLevel(texture, uv, textureLevelOfDetail(texture, one));
        for (int c = 0; c < 4; ++c)
          EXPECT_EQ(std::bit_cast<std::uint32_t>(whole[c]), std::bit_cast<std::uint32_t>(split[c]));
      }
  }
}

TEST(TextureMips, NearestLevelAndNoLevelsAsMinFilterSays) {
  Texture texture = gradient(8, 8, TextureMipmap::Nearest);
  const glm::vec2 uv(0.375f, 0.125f), uv2(0.25f, 0.25f);  // centres of level 1's texel (1, 0), level 2's (0, 0)
  EXPECT_EQ(sampleTexture(texture, uv, footprintOf(1.4f, 8)), texelOf(texture.mipLevels[0], 1, 0));
  EXPECT_EQ(sampleTexture(texture, uv2, footprintOf(1.6f, 8)), texelOf(texture.mipLevels[1], 0, 0));
  EXPECT_EQ(sampleTexture(texture, uv, footprintOf(0.4f, 8)), sampleTexture(texture, uv)) << "⌈λ + ½⌉ − 1 = 0";
  // No levels: a minified texture samples level 0 with minFilter, not magFilter.
  texture.mipmap = TextureMipmap::None;
  texture.mipLevels.clear();
  texture.magFilter = TextureFilter::Linear;
  texture.minFilter = TextureFilter::Nearest;
  const glm::vec2 inTexel30(0.375f, 0.0625f);  // texel (3, 0)'s left edge: nearest gives it, bilinear does not
  EXPECT_EQ(sampleTexture(texture, inTexel30, footprintOf(2.0f, 8)), glm::vec4(48, 255 - 48, 7, 255) / 255.0f);
  EXPECT_NE(sampleTexture(texture, inTexel30), glm::vec4(48, 255 - 48, 7, 255) / 255.0f) << "magnified: bilinear";
}

TEST(TextureMips, ALongFootprintIsCoveredByProbesAtTheLevelOfItsShortSide) {
  // Rows in bands of four texels, black and white; a footprint 8 texels along u and one along v, as a floor
  // seen at a slant gives: one probe sized by the long side (level 3) would average two bands to grey.
  Texture bands;
  bands.width = bands.height = 32;
  bands.rgba8.resize(32 * 32 * 4);
  for (std::size_t texel = 0; texel < 32 * 32; ++texel) {
    const std::uint8_t value = (texel / 32) % 8 < 4 ? 0 : 255;
    for (int c = 0; c < 3; ++c) bands.rgba8[texel * 4 + c] = value;
    bands.rgba8[texel * 4 + 3] = 255;
  }
  bands.mipmap = TextureMipmap::Linear;
  buildMipLevels(bands);
  const glm::vec2 whiteBand(0.3f, 6.0f / 32.0f);  // row 6: the middle of the first white band
  const TextureFootprint slanted{glm::vec2(8.0f / 32.0f, 0.0f), glm::vec2(0.0f, 1.0f / 32.0f), 4};
  EXPECT_GT(sampleTexture(bands, whiteBand, slanted).r, 0.9f) << "4 probes of 2 × 1 texels: level 1, bands kept";
  const TextureFootprint oneProbe{slanted.dx, slanted.dy, 1};
  EXPECT_NEAR(sampleTexture(bands, whiteBand, oneProbe).r, 0.5f, 0.05f) << "OpenGL's isotropic rule: level 3";
  const TextureFootprint square{glm::vec2(8.0f / 32.0f, 0.0f), glm::vec2(0.0f, 8.0f / 32.0f)};
  EXPECT_NEAR(sampleTexture(bands, whiteBand, square).r, 0.5f, 0.05f) << "8 × 8 texels: two bands, grey";
  // The same along v, and a footprint barely longer than wide takes one probe: the isotropic level.
  const TextureFootprint turned{glm::vec2(1.0f / 32.0f, 0.0f), glm::vec2(0.0f, 8.0f / 32.0f), 4};
  EXPECT_NEAR(sampleTexture(bands, whiteBand, turned).r, 0.5f, 0.1f) << "long across the bands: they average";
  const TextureFootprint nearlySquare{glm::vec2(4.0f / 32.0f, 0.0f), glm::vec2(0.0f, 3.0f / 32.0f), 4};
  const TextureFootprint isotropic{glm::vec2(4.0f / 32.0f, 0.0f), glm::vec2(0.0f, 4.0f / 32.0f)};
  EXPECT_EQ(sampleTexture(bands, whiteBand, nearlySquare), sampleTexture(bands, whiteBand, isotropic));
}

}  // namespace
}  // namespace pbs
