// Framebuffer allocation and clearing: depth always, every other channel only when asked for.
#include "pbs/raster/framebuffer.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

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

void clearFramebuffer(Framebuffer& framebuffer, ChannelMask channels) {
  // Clearing a full G-buffer is tens of MB of stores, as long as drawing a small mesh into it: it
  // runs on every thread of the arena, in row bands (each byte written once, so no order issue).
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, framebuffer.pixelCount(), 1 << 16), [&](const auto& range) {
    const auto fill = [&](auto& channel, bool wanted, const auto& value) {
      if (wanted && !channel.empty())
        std::fill(channel.begin() + std::ptrdiff_t(range.begin()), channel.begin() + std::ptrdiff_t(range.end()), value);
    };
    fill(framebuffer.depth, true, kClearDepth);
    fill(framebuffer.color, channels & kChannelColor, glm::u8vec4(0));
    fill(framebuffer.position, channels & kChannelPosition, glm::vec3(0.0f));
    fill(framebuffer.normal, channels & kChannelNormal, glm::vec3(0.0f));
    fill(framebuffer.ids, channels & kChannelIds, PixelIds{});
  });
}

void resizeFramebuffer(Framebuffer& framebuffer, std::uint32_t width, std::uint32_t height) {
  framebuffer.width = width;
  framebuffer.height = height;
  const std::size_t pixels = framebuffer.pixelCount();
  const auto resize = [&](auto& channel, bool allocated) {
    if (allocated) channel.resize(pixels);
  };
  resize(framebuffer.depth, true);
  resize(framebuffer.color, framebuffer.has(kChannelColor));
  resize(framebuffer.position, framebuffer.has(kChannelPosition));
  resize(framebuffer.normal, framebuffer.has(kChannelNormal));
  resize(framebuffer.ids, framebuffer.has(kChannelIds));
}

}  // namespace pbs
