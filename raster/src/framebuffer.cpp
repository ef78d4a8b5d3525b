// Framebuffer allocation and clearing: depth always, every other channel only when asked for.
#include "pbs/raster/framebuffer.hpp"

#include <algorithm>

namespace pbs {

Framebuffer makeFramebuffer(std::uint32_t width, std::uint32_t height, ChannelMask channels,
                            const glm::dvec3& positionOrigin) {
  Framebuffer framebuffer;
  framebuffer.width = width;
  framebuffer.height = height;
  framebuffer.channels = channels;
  framebuffer.positionOrigin = positionOrigin;
  const std::size_t pixels = framebuffer.pixelCount();
  framebuffer.depth.assign(pixels, kClearDepth);
  if (framebuffer.has(kChannelColor)) framebuffer.color.assign(pixels, glm::u8vec4(0));
  if (framebuffer.has(kChannelPosition)) framebuffer.position.assign(pixels, glm::vec3(0.0f));
  if (framebuffer.has(kChannelNormal)) framebuffer.normal.assign(pixels, glm::vec3(0.0f));
  if (framebuffer.has(kChannelIds)) framebuffer.ids.assign(pixels, PixelIds{});
  return framebuffer;
}

void clearFramebuffer(Framebuffer& framebuffer) {
  std::fill(framebuffer.depth.begin(), framebuffer.depth.end(), kClearDepth);
  std::fill(framebuffer.color.begin(), framebuffer.color.end(), glm::u8vec4(0));
  std::fill(framebuffer.position.begin(), framebuffer.position.end(), glm::vec3(0.0f));
  std::fill(framebuffer.normal.begin(), framebuffer.normal.end(), glm::vec3(0.0f));
  std::fill(framebuffer.ids.begin(), framebuffer.ids.end(), PixelIds{});
}

}  // namespace pbs
