// upscaleBilinear: input rows interpolated along x, then output rows between two of them, two pixels at a time.
#include "pbs/raster/image_upscale.hpp"

#include "pbs/raster/headlight_shading.hpp"
#include "pbs/raster/simd_clones.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
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

// The input's rows, and where each output column and row falls in it.
struct Upscale {
  const UpscaleRows& source;
  std::uint32_t width = 0;
  std::vector<Tap> columns, rows;
};

Upscale prepare(const UpscaleRows& rows, std::uint32_t width, std::uint32_t height, std::uint32_t toWidth,
                std::uint32_t toHeight) {
  if (width == 0 || height == 0 || toWidth == 0 || toHeight == 0)
    throw std::invalid_argument("upscaleBilinear: an image of no pixels");
  return {rows, width, taps(width, toWidth), taps(height, toHeight)};
}

// The rows of an image held whole.
UpscaleRows rowsOf(std::span<const glm::vec4> image, std::uint32_t width, std::uint32_t height) {
  if (image.size() != std::size_t(width) * height)
    throw std::invalid_argument("upscaleBilinear: the image is not width × height");
  return [image, width](std::uint32_t y, glm::vec4*) { return image.data() + std::size_t(y) * width; };
}

// Input rows premultiplied and interpolated along x to the output's width, the last two a task used: consecutive output
// rows fall between the same two input rows (three of them at a third of the size), which are widened once. Lines hold
// an even number of pixels (the last one repeated) for the two-pixel steps below.
class WideRows {
 public:
  explicit WideRows(const Upscale& u)
      : u_(u),
        pairs_((u.columns.size() + 1) / 2),
        lines_{std::vector<glm::vec4>(pairs_ * 2), std::vector<glm::vec4>(pairs_ * 2)},
        input_(u.width) {}

  std::size_t pairs() const { return pairs_; }

  // Input row `y` widened, without evicting row `keep` (the other row the caller needs).
  PBS_CLONE_INLINE const glm::vec4* row(std::uint32_t y, std::uint32_t keep) {
    for (int slot = 0; slot < 2; ++slot)
      if (rows_[slot] == y) return lines_[slot].data();
    const int slot = rows_[0] == keep ? 1 : 0;
    rows_[slot] = y;
    glm::vec4* line = lines_[slot].data();
    const glm::vec4* input = u_.source(y, input_.data());
    const std::size_t width = u_.columns.size();
    for (std::size_t x = 0; x < width; ++x) {
      const Tap& column = u_.columns[x];
      line[x] = lerp(premultiplied(input[column.first]), premultiplied(input[column.second]), column.weight);
    }
    if (width % 2) line[width] = line[width - 1];
    return line;
  }

 private:
  const Upscale& u_;
  std::size_t pairs_;
  std::vector<glm::vec4> lines_[2];
  std::vector<glm::vec4> input_;  // the scratch row the source may fill
  std::uint32_t rows_[2] = {UINT32_MAX, UINT32_MAX};
};

// Two pixels' channels in one vector (a 256-bit register in the AVX2 clones).
typedef float PixelPair __attribute__((vector_size(32)));

// Output rows [y0, y1): each interpolated between its two widened input rows, two pixels at a time, and
// handed un-premultiplied to store(index of the first pixel, the pair, pixels of it to keep: 2, or 1 at an
// odd row's end).
template <class Store>
PBS_CLONE_INLINE void upscaleRows(const Upscale& u, std::uint32_t y0, std::uint32_t y1, Store&& store) {
  WideRows wide(u);
  const std::size_t toWidth = u.columns.size();
  for (std::uint32_t y = y0; y < y1; ++y) {
    const Tap& tap = u.rows[y];
    const glm::vec4* top = wide.row(tap.first, tap.second);
    const glm::vec4* bottom = wide.row(tap.second, tap.first);
    for (std::size_t pair = 0; pair < wide.pairs(); ++pair) {
      PixelPair a, b;
      std::memcpy(&a, top + 2 * pair, sizeof a);
      std::memcpy(&b, bottom + 2 * pair, sizeof b);
      const PixelPair c = a + (b - a) * tap.weight;
      // Straight colour where alpha is positive (alpha itself kept), nothing where it is not.
      const PixelPair alpha = __builtin_shufflevector(c, c, 3, 3, 3, 3, 7, 7, 7, 7);
      const PixelPair zero = {}, one = zero + 1.0f;
      const PixelPair divided = c / (alpha > zero ? alpha : one);
      const PixelPair dividedColour = __builtin_shufflevector(divided, c, 0, 1, 2, 11, 4, 5, 6, 15);
      const PixelPair straight = alpha > zero ? dividedColour : zero;
      const std::size_t x = 2 * pair;
      store(std::size_t(y) * toWidth + x, straight, x + 1 < toWidth ? 2 : 1);
    }
  }
}

// The two outputs' row loops, each compiled for AVX2 beside the baseline (bit for bit the same).
PBS_AVX2_CLONES void upscaleRowsFloat(const Upscale& u, std::uint32_t y0, std::uint32_t y1, glm::vec4* out) {
  upscaleRows(u, y0, y1, [&](std::size_t i, const PixelPair& pair, int pixels) {
    if (pixels == 2)
      std::memcpy(out + i, &pair, sizeof pair);
    else
      std::memcpy(out + i, &pair, sizeof(glm::vec4));
  });
}

PBS_AVX2_CLONES void upscaleRowsRgba8(const Upscale& u, std::uint32_t y0, std::uint32_t y1, std::uint8_t* out) {
  typedef std::int32_t Ints __attribute__((vector_size(32)));
  typedef std::uint8_t Bytes __attribute__((vector_size(32)));
  upscaleRows(u, y0, y1, [&](std::size_t i, const PixelPair& pair, int pixels) {
    Ints rounded;
    roundToBytes(pair, rounded);
    const Bytes lanes = Bytes(rounded);
    const auto bytes = __builtin_shufflevector(lanes, lanes, 0, 4, 8, 12, 16, 20, 24, 28);
    if (pixels == 2)
      std::memcpy(out + i * 4, &bytes, 8);  // a constant size: one store
    else
      std::memcpy(out + i * 4, &bytes, 4);
  });
}

// Calls rows(first, last) over the output rows in parallel.
template <class Rows>
void forRows(std::uint32_t toHeight, Rows&& rows) {
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, toHeight),
                    [&](const tbb::blocked_range<std::uint32_t>& r) { rows(r.begin(), r.end()); });
}

}  // namespace

std::vector<glm::vec4> upscaleBilinear(const UpscaleRows& rows, std::uint32_t width, std::uint32_t height,
                                       std::uint32_t toWidth, std::uint32_t toHeight) {
  const Upscale u = prepare(rows, width, height, toWidth, toHeight);
  std::vector<glm::vec4> result(std::size_t(toWidth) * toHeight);
  forRows(toHeight, [&](std::uint32_t y0, std::uint32_t y1) { upscaleRowsFloat(u, y0, y1, result.data()); });
  return result;
}

std::vector<glm::vec4> upscaleBilinear(std::span<const glm::vec4> image, std::uint32_t width, std::uint32_t height,
                                       std::uint32_t toWidth, std::uint32_t toHeight) {
  return upscaleBilinear(rowsOf(image, width, height), width, height, toWidth, toHeight);
}

std::vector<std::uint8_t> upscaleBilinearRgba8(const UpscaleRows& rows, std::uint32_t width, std::uint32_t height,
                                               std::uint32_t toWidth, std::uint32_t toHeight) {
  const Upscale u = prepare(rows, width, height, toWidth, toHeight);
  std::vector<std::uint8_t> result(std::size_t(toWidth) * toHeight * 4);
  forRows(toHeight, [&](std::uint32_t y0, std::uint32_t y1) { upscaleRowsRgba8(u, y0, y1, result.data()); });
  return result;
}

std::vector<std::uint8_t> upscaleBilinearRgba8(std::span<const glm::vec4> image, std::uint32_t width,
                                               std::uint32_t height, std::uint32_t toWidth, std::uint32_t toHeight) {
  return upscaleBilinearRgba8(rowsOf(image, width, height), width, height, toWidth, toHeight);
}

}  // namespace pbs
