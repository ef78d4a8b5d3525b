// The colour scale for FLIP maps: dark for no error, bright for the most, brightness rising throughout.
#include <pbs/raster/flip.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace pbs {
namespace {

// Black, violet, crimson, coral, amber, cream at equal steps, every channel non-decreasing from one to
// the next, so that any brightness measure rises with the error; the hue turns to make neighbouring
// levels easier to tell apart than on a grey ramp.
constexpr std::array<glm::vec3, 6> kControlPoints = {{
    {0.0f, 0.0f, 0.0f},
    {40.0f, 0.0f, 90.0f},
    {150.0f, 20.0f, 110.0f},
    {230.0f, 100.0f, 110.0f},
    {250.0f, 190.0f, 120.0f},
    {255.0f, 252.0f, 220.0f},
}};

}  // namespace

std::vector<std::uint8_t> flipMapRgba8(std::span<const float> map) {
  std::vector<std::uint8_t> rgba(map.size() * 4);
  constexpr float segments = float(kControlPoints.size() - 1);
  for (std::size_t i = 0; i < map.size(); ++i) {
    // Written so that NaN fails the first test and becomes 0.
    const float value = map[i] > 0.0f ? std::min(map[i], 1.0f) : 0.0f;
    const float position = value * segments;
    const std::size_t segment = std::min(std::size_t(position), kControlPoints.size() - 2);
    const float t = position - float(segment);
    const glm::vec3 colour = glm::mix(kControlPoints[segment], kControlPoints[segment + 1], t);
    for (int c = 0; c < 3; ++c) rgba[4 * i + std::size_t(c)] = std::uint8_t(std::lround(colour[c]));
    rgba[4 * i + 3] = 255;
  }
  return rgba;
}

}  // namespace pbs
