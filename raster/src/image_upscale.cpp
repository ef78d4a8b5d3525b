// upscaleBilinear: each output row reads two input rows, each output pixel four input pixels.
#include "pbs/raster/image_upscale.hpp"

#include "pbs/raster/headlight_shading.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace pbs {
namespace {

// Where output pixel i's centre falls between input pixels: the two pixels and the weight of the second.
struct Tap {
  std::uint32_t first, second;
  float weight;
};

std::vector<Tap> taps(std::uint32_t from, std::uint32_t to) {
  std::vector<Tap> result(to);
  const double ratio = double(from) / double(to);
  for (std::uint32_t i = 0; i < to; ++i) {
    const double at = std::clamp((double(i) + 0.5) * ratio - 0.5, 0.0, double(from - 1));
    const auto first = std::uint32_t(at);
    result[i] = {first, std::min(first + 1, from - 1), float(at - double(first))};
  }
  return result;
}

glm::vec4 premultiplied(const glm::vec4& c) { return {glm::vec3(c) * c.a, c.a}; }

// a + (b − a) t: exactly a where b equals it (glm::mix's a (1 − t) + b t is not), so flat regions stay flat.
glm::vec4 lerp(const glm::vec4& a, const glm::vec4& b, float t) { return a + (b - a) * t; }

// Calls store(index, colour) for every output pixel, rows in parallel. The image is premultiplied once; each
// output row is first interpolated between its two input rows, then along itself.
template <class Store>
void upscale(std::span<const glm::vec4> image, std::uint32_t width, std::uint32_t height, std::uint32_t toWidth,
             std::uint32_t toHeight, Store&& store) {
  if (width == 0 || height == 0 || toWidth == 0 || toHeight == 0)
    throw std::invalid_argument("upscaleBilinear: an image of no pixels");
  if (image.size() != std::size_t(width) * height)
    throw std::invalid_argument("upscaleBilinear: the image is not width × height");
  const std::vector<Tap> columns = taps(width, toWidth), rows = taps(height, toHeight);
  std::vector<glm::vec4> source(image.size());
  for (std::size_t i = 0; i < image.size(); ++i) source[i] = premultiplied(image[i]);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, toHeight), [&](const tbb::blocked_range<std::uint32_t>& r) {
    std::vector<glm::vec4> line(width);
    for (std::uint32_t y = r.begin(); y != r.end(); ++y) {
      const Tap& row = rows[y];
      const glm::vec4* top = source.data() + std::size_t(row.first) * width;
      const glm::vec4* bottom = source.data() + std::size_t(row.second) * width;
      for (std::uint32_t x = 0; x < width; ++x) line[x] = lerp(top[x], bottom[x], row.weight);
      for (std::uint32_t x = 0; x < toWidth; ++x) {
        const Tap& column = columns[x];
        const glm::vec4 c = lerp(line[column.first], line[column.second], column.weight);
        store(std::size_t(y) * toWidth + x, c.a > 0.0f ? glm::vec4(glm::vec3(c) / c.a, c.a) : glm::vec4(0.0f));
      }
    }
  });
}

}  // namespace

std::vector<glm::vec4> upscaleBilinear(std::span<const glm::vec4> image, std::uint32_t width, std::uint32_t height,
                                       std::uint32_t toWidth, std::uint32_t toHeight) {
  std::vector<glm::vec4> result(std::size_t(toWidth) * toHeight);
  upscale(image, width, height, toWidth, toHeight, [&](std::size_t i, const glm::vec4& c) { result[i] = c; });
  return result;
}

std::vector<std::uint8_t> upscaleBilinearRgba8(std::span<const glm::vec4> image, std::uint32_t width,
                                               std::uint32_t height, std::uint32_t toWidth, std::uint32_t toHeight) {
  std::vector<std::uint8_t> result(std::size_t(toWidth) * toHeight * 4);
  upscale(image, width, height, toWidth, toHeight, [&](std::size_t i, const glm::vec4& c) {
    const glm::u8vec4 unorm = toRgba8(c);
    std::memcpy(&result[i * 4], &unorm, 4);
  });
  return result;
}

}  // namespace pbs
