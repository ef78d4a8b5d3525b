// A decoded RGBA8 image with the sampler that reads it (glTF's wrap and filter modes).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace pbs {

enum class TextureWrap : std::uint8_t { Repeat, ClampToEdge, MirroredRepeat };
enum class TextureFilter : std::uint8_t { Nearest, Linear };

struct Texture {
  std::string name;
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<std::uint8_t> rgba8;  // width * height * 4 bytes, top row first
  TextureWrap wrapS = TextureWrap::Repeat;
  TextureWrap wrapT = TextureWrap::Repeat;
  TextureFilter magFilter = TextureFilter::Linear;
  TextureFilter minFilter = TextureFilter::Linear;
};

// Whether the texture holds the pixels its size promises (anything else is drawn untextured).
bool isSampleable(const Texture& texture);

// RGBA in [0, 1] at texture coordinate uv ((0, 0) is the first texel's corner, v grows downwards
// through the rows as glTF has it; texel centres sit at half-integers): bilinear, or nearest when
// magFilter says so, with the texture's wrap modes. The rasterizer and the ray caster share it, so
// their colours agree.
glm::vec4 sampleTexture(const Texture& texture, glm::vec2 uv);

// A colour in [0, 1] as RGBA8, rounded to nearest; out-of-range values clamp and NaN becomes 0.
glm::u8vec4 toUnorm8(const glm::vec4& color);

}  // namespace pbs
