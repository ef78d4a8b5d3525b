// Framebuffer allocation and clearing: depth always, every other channel only when asked for.
#include "pbs/raster/framebuffer.hpp"

#include "pbs/raster/value_names.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace pbs {
namespace {

// Calls visit(values, channel, clear value) for depth (channel 0: always there) and each optional
// channel, so that allocating, clearing and resizing name the channels and their clear values once.
template <class Visit>
void forEachChannel(Framebuffer& framebuffer, Visit&& visit) {
  visit(framebuffer.depth, ChannelMask{0}, kClearDepth);
  visit(framebuffer.color, ChannelMask{kChannelColor}, glm::u8vec4(0));
  visit(framebuffer.position, ChannelMask{kChannelPosition}, glm::vec3(0.0f));
  visit(framebuffer.normal, ChannelMask{kChannelNormal}, glm::vec3(0.0f));
  visit(framebuffer.ids, ChannelMask{kChannelIds}, PixelIds{});
  visit(framebuffer.coverage, ChannelMask{kChannelCoverage}, 0.0f);
}

constexpr ValueNames<Channel, 5> kChannelNames{{{{kChannelColor, "color"},
                                                 {kChannelPosition, "position"},
                                                 {kChannelNormal, "normal"},
                                                 {kChannelIds, "ids"},
                                                 {kChannelCoverage, "coverage"}}}};

bool allocated(const Framebuffer& framebuffer, ChannelMask channel) {
  return channel == 0 || (framebuffer.channels & channel) != 0;
}

}  // namespace

std::vector<std::string_view> channelNames(ChannelMask channels) {
  std::vector<std::string_view> names{"depth"};
  for (const auto& [channel, name] : kChannelNames.entries)
    if ((channels & channel) != 0) names.push_back(name);
  return names;
}

Framebuffer makeFramebuffer(std::uint32_t width, std::uint32_t height, ChannelMask channels,
                            const glm::dvec3& positionOrigin) {
  Framebuffer framebuffer;
  framebuffer.width = width;
  framebuffer.height = height;
  framebuffer.channels = channels;
  framebuffer.positionOrigin = positionOrigin;
  const std::size_t pixels = framebuffer.pixelCount();
  forEachChannel(framebuffer, [&](auto& values, ChannelMask channel, const auto& clearValue) {
    if (allocated(framebuffer, channel)) values.assign(pixels, clearValue);
  });
  return framebuffer;
}

void clearFramebuffer(Framebuffer& framebuffer, ChannelMask channels) {
  // Clearing a full G-buffer is tens of MB of stores, as long as drawing a small mesh into it: it
  // runs on every thread of the arena, in row bands (each byte written once, so no order issue).
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, framebuffer.pixelCount(), 1 << 16), [&](const auto& range) {
    forEachChannel(framebuffer, [&](auto& values, ChannelMask channel, const auto& clearValue) {
      const bool wanted = channel == 0 || (channels & channel) != 0;
      if (wanted && !values.empty())
        std::fill(values.begin() + std::ptrdiff_t(range.begin()), values.begin() + std::ptrdiff_t(range.end()),
                  clearValue);
    });
  });
}

void resizeFramebuffer(Framebuffer& framebuffer, std::uint32_t width, std::uint32_t height) {
  framebuffer.width = width;
  framebuffer.height = height;
  const std::size_t pixels = framebuffer.pixelCount();
  forEachChannel(framebuffer, [&](auto& values, ChannelMask channel, const auto&) {
    if (allocated(framebuffer, channel)) values.resize(pixels);
  });
}

}  // namespace pbs
