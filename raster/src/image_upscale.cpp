// upscaleBilinear: each output row reads two input rows, each output pixel four input pixels.
#include "pbs/raster/image_upscale.hpp"

#include "pbs/raster/headlight_shading.hpp"
#include "pbs/raster/simd_clones.hpp"

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

PBS_CLONE_INLINE glm::vec4 premultiplied(const glm::vec4& c) { return {glm::vec3(c) * c.a, c.a}; }

// a + (b − a) t: exactly a where b equals it (glm::mix's a (1 − t) + b t is not), so flat regions stay flat.
PBS_CLONE_INLINE glm::vec4 lerp(const glm::vec4& a, const glm::vec4& b, float t) { return a + (b - a) * t; }

// The input premultiplied once, and where each output column and row falls in it.
struct Upscale {
  std::vector<glm::vec4> source;
  std::uint32_t width = 0;
  std::vector<Tap> columns, rows;
};

Upscale prepare(std::span<const glm::vec4> image, std::uint32_t width, std::uint32_t height, std::uint32_t toWidth,
                std::uint32_t toHeight) {
  if (width == 0 || height == 0 || toWidth == 0 || toHeight == 0)
    throw std::invalid_argument("upscaleBilinear: an image of no pixels");
  if (image.size() != std::size_t(width) * height)
    throw std::invalid_argument("upscaleBilinear: the image is not width × height");
  Upscale u{std::vector<glm::vec4>(image.size()), width, taps(width, toWidth), taps(height, toHeight)};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, image.size(), std::size_t(1) << 14),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i) u.source[i] = premultiplied(image[i]);
                    });
  return u;
}

// Output rows [y0, y1): each interpolated between its two input rows into `line`, then along itself, each
// pixel handed to store(index, straight colour).
template <class Store>
PBS_CLONE_INLINE void upscaleRows(const Upscale& u, std::uint32_t y0, std::uint32_t y1, std::vector<glm::vec4>& line,
                                  Store&& store) {
  const auto toWidth = std::uint32_t(u.columns.size());
  for (std::uint32_t y = y0; y < y1; ++y) {
    const Tap& row = u.rows[y];
    const glm::vec4* top = u.source.data() + std::size_t(row.first) * u.width;
    const glm::vec4* bottom = u.source.data() + std::size_t(row.second) * u.width;
    for (std::uint32_t x = 0; x < u.width; ++x) line[x] = lerp(top[x], bottom[x], row.weight);
    for (std::uint32_t x = 0; x < toWidth; ++x) {
      const Tap& column = u.columns[x];
      const glm::vec4 c = lerp(line[column.first], line[column.second], column.weight);
      store(std::size_t(y) * toWidth + x, c.a > 0.0f ? glm::vec4(glm::vec3(c) / c.a, c.a) : glm::vec4(0.0f));
    }
  }
}

// The two outputs' row loops, each compiled for AVX2 beside the baseline (the interpolation and the 8-bit
// rounding vectorise; bit for bit the same).
PBS_AVX2_CLONES void upscaleRowsFloat(const Upscale& u, std::uint32_t y0, std::uint32_t y1,
                                      std::vector<glm::vec4>& line, glm::vec4* out) {
  upscaleRows(u, y0, y1, line, [&](std::size_t i, const glm::vec4& c) { out[i] = c; });
}

PBS_AVX2_CLONES void upscaleRowsRgba8(const Upscale& u, std::uint32_t y0, std::uint32_t y1,
                                      std::vector<glm::vec4>& line, std::uint8_t* out) {
  upscaleRows(u, y0, y1, line, [&](std::size_t i, const glm::vec4& c) {
    const glm::u8vec4 unorm = toRgba8(c);
    std::memcpy(out + i * 4, &unorm, 4);
  });
}

// Calls rows(first, last, line) over the output rows in parallel, each task with its own line buffer.
template <class Rows>
void forRows(const Upscale& u, std::uint32_t toHeight, Rows&& rows) {
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, toHeight), [&](const tbb::blocked_range<std::uint32_t>& r) {
    std::vector<glm::vec4> line(u.width);
    rows(r.begin(), r.end(), line);
  });
}

}  // namespace

std::vector<glm::vec4> upscaleBilinear(std::span<const glm::vec4> image, std::uint32_t width, std::uint32_t height,
                                       std::uint32_t toWidth, std::uint32_t toHeight) {
  const Upscale u = prepare(image, width, height, toWidth, toHeight);
  std::vector<glm::vec4> result(std::size_t(toWidth) * toHeight);
  forRows(u, toHeight, [&](std::uint32_t y0, std::uint32_t y1, std::vector<glm::vec4>& line) {
    upscaleRowsFloat(u, y0, y1, line, result.data());
  });
  return result;
}

std::vector<std::uint8_t> upscaleBilinearRgba8(std::span<const glm::vec4> image, std::uint32_t width,
                                               std::uint32_t height, std::uint32_t toWidth, std::uint32_t toHeight) {
  const Upscale u = prepare(image, width, height, toWidth, toHeight);
  std::vector<std::uint8_t> result(std::size_t(toWidth) * toHeight * 4);
  forRows(u, toHeight, [&](std::uint32_t y0, std::uint32_t y1, std::vector<glm::vec4>& line) {
    upscaleRowsRgba8(u, y0, y1, line, result.data());
  });
  return result;
}

}  // namespace pbs
