// G-buffers: depth plus only the channels a draw asks for (colour, position, normal, ids).
#pragma once

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string_view>
#include <vector>

namespace pbs {

enum Channel : std::uint32_t {
  kChannelColor = 1u << 0,     // base colour (material factor × texture), RGBA8
  kChannelPosition = 1u << 1,  // world position − Framebuffer::positionOrigin, float3
  kChannelNormal = 1u << 2,    // world-space unit normal, float3
  kChannelIds = 1u << 3,       // node, instance and primitive ids, 32 bits each
  // Fraction of the pixel the surface covers, float in [0, 1]: only blended splats (blended_splats.hpp)
  // leave a covered pixel partly covered, so only frames drawing them allocate it.
  kChannelCoverage = 1u << 4,
};
using ChannelMask = std::uint32_t;
inline constexpr ChannelMask kAllChannels =
    kChannelColor | kChannelPosition | kChannelNormal | kChannelIds | kChannelCoverage;

struct PixelIds {
  std::uint32_t node = 0xffffffffu;
  std::uint32_t instance = 0xffffffffu;
  std::uint32_t primitive = 0xffffffffu;  // triangle index within its mesh, or point index within its set
  bool operator==(const PixelIds&) const = default;
};

inline constexpr float kClearDepth = std::numeric_limits<float>::infinity();

// Row-major, row 0 at the top. A channel not in `channels` stays an empty vector: never allocated,
// never written.
struct Framebuffer {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  ChannelMask channels = 0;
  // Positions are stored relative to this origin, so float keeps its digits for scenes far from
  // the world origin (the capture of a node uses the node's centre).
  glm::dvec3 positionOrigin{0.0};

  std::vector<float> depth;  // window depth in [0, 1]; kClearDepth where nothing was drawn
  std::vector<glm::u8vec4> color;
  std::vector<glm::vec3> position;
  std::vector<glm::vec3> normal;
  std::vector<PixelIds> ids;
  std::vector<float> coverage;

  bool has(Channel channel) const { return (channels & channel) != 0; }
  bool covered(std::size_t pixel) const { return depth[pixel] != kClearDepth; }
  std::size_t pixelCount() const { return std::size_t(width) * height; }
};

// A framebuffer's bytes per pixel with depth and exactly `channels`.
constexpr std::size_t framebufferBytesPerPixel(ChannelMask channels) {
  return sizeof(float) + ((channels & kChannelColor) ? sizeof(glm::u8vec4) : 0) +
         ((channels & kChannelPosition) ? sizeof(glm::vec3) : 0) +
         ((channels & kChannelNormal) ? sizeof(glm::vec3) : 0) + ((channels & kChannelIds) ? sizeof(PixelIds) : 0) +
         ((channels & kChannelCoverage) ? sizeof(float) : 0);
}

// For reports of what a run used: "depth" (always there), then the names of the channels in `channels`
// ("color", "position", "normal", "ids", "coverage"), in that order.
std::vector<std::string_view> channelNames(ChannelMask channels);

// Allocates depth and exactly the requested channels, cleared (colour to 0, ids to all ones).
Framebuffer makeFramebuffer(std::uint32_t width, std::uint32_t height, ChannelMask channels,
                            const glm::dvec3& positionOrigin = glm::dvec3(0.0));

// Clears depth and, of the other allocated channels, those in `channels` (all by default). A channel
// left out keeps its old values, which then mean something only where depth says a pixel is
// covered: a reader that looks only there (as the surfel capture does) can clear depth alone and
// skip the rest of a colour + position + normal G-buffer, 28 of its 32 bytes a pixel.
void clearFramebuffer(Framebuffer& framebuffer, ChannelMask channels = kAllChannels);

// A new size for the same channels, reusing their memory where it suffices (the views of a capture
// differ in size); the pixels' values are unspecified until the framebuffer is cleared.
void resizeFramebuffer(Framebuffer& framebuffer, std::uint32_t width, std::uint32_t height);

}  // namespace pbs
