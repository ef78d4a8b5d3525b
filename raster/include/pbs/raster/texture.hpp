// A decoded RGBA8 image with the sampler that reads it (glTF's wrap and filter modes).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace pbs {

enum class TextureWrap : std::uint8_t { Repeat, ClampToEdge, MirroredRepeat };
enum class TextureFilter : std::uint8_t { Nearest, Linear };
// glTF's minFilter has two parts: the filter within a level (TextureFilter) and how levels of the mip
// chain are used: none (level 0 only), the nearest level, or a blend of the two nearest.
enum class TextureMipmap : std::uint8_t { None, Nearest, Linear };

// One level of a mip chain: width × height RGBA8 texels, top row first.
struct TextureLevel {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<std::uint8_t> rgba8;
};

struct Texture {
  std::string name;
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<std::uint8_t> rgba8;  // width * height * 4 bytes, top row first
  TextureWrap wrapS = TextureWrap::Repeat;
  TextureWrap wrapT = TextureWrap::Repeat;
  TextureFilter magFilter = TextureFilter::Linear;
  TextureFilter minFilter = TextureFilter::Linear;
  TextureMipmap mipmap = TextureMipmap::None;
  // Levels 1, 2, … of the mip chain down to 1 × 1 (level 0 is the image above), made by buildMipLevels
  // for a texture whose minFilter uses them; without them a minified texture samples level 0.
  std::vector<TextureLevel> mipLevels{};
};

// Whether the texture holds the pixels its size promises (anything else is drawn untextured).
bool isSampleable(const Texture& texture);

// Fills mipLevels where `mipmap` asks for them (else leaves none): each level halves the one before
// (sizes rounded down, at least 1, as OpenGL has them), a texel the rounded mean of the 2 × 2 texels it
// covers (an odd size's last row or column is left out; a size of 1 repeats its one row or column).
// Integer arithmetic: the same bytes on every machine.
void buildMipLevels(Texture& texture);

// How far the texture coordinate moves across one sample of the image: d(uv)/dx and d(uv)/dy per window
// pixel, times the spacing of the samples (Camera::sampleSpacing). Zero (the default) samples level 0.
// maxProbes: the most probes along a footprint longer than wide (Camera::textureProbes); 0 leaves the footprint
// unused: level 0 is sampled as if magnified, with no mip level and no probe (the fastest, and aliased).
struct TextureFootprint {
  glm::vec2 dx{0.0f};
  glm::vec2 dy{0.0f};
  std::uint32_t maxProbes = 1;
};

// RGBA in [0, 1] at texture coordinate uv ((0, 0) is the first texel's corner, v grows downwards
// through the rows as glTF has it; texel centres sit at half-integers), with the texture's wrap modes.
// A footprint's side in texels of level 0 sets the level of detail λ = log2 of it (OpenGL's rule): up
// to λ = 0 the texture is magnified (magFilter on level 0), beyond it minified (minFilter on the level
// or levels `mipmap` picks). A footprint n times longer than wide (rounded, at most maxProbes) is
// sampled by n probes spaced along its long side, each at the level of 1/n of that side. The rasterizer
// and the ray caster share this, and compute the footprint the same way (from the triangle's projection
// at the sample), so their colours agree.
glm::vec4 sampleTexture(const Texture& texture, glm::vec2 uv, const TextureFootprint& footprint = {});

// sampleTexture for a footprint of one probe (maxProbes 1) split in two, for a caller whose footprint is the same
// at many samples (an affine triangle's, in an orthographic view): the level of detail it gives (NaN where it has
// no side: level 0 magnified), then the sample at a level. sampleTextureAtLevel(t, uv, textureLevelOfDetail(t, f))
// is sampleTexture(t, uv, f) to the bit.
float textureLevelOfDetail(const Texture& texture, const TextureFootprint& footprint);
glm::vec4 sampleTextureAtLevel(const Texture& texture, glm::vec2 uv, float lod);

// A colour in [0, 1] as RGBA8, rounded to nearest; out-of-range values clamp and NaN becomes 0. Inline, so
// that the resolve's clones inline it per pixel.
inline glm::u8vec4 toUnorm8(const glm::vec4& color) {
  const auto unorm8 = [](float v) {
    const float clamped = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
    return std::uint8_t(clamped * 255.0f + 0.5f);
  };
  return {unorm8(color.r), unorm8(color.g), unorm8(color.b), unorm8(color.a)};
}

}  // namespace pbs
