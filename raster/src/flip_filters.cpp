// The column and row passes of FLIP's separable filters, vectorised across the pixels of a row.
#include "flip_filters.hpp"

#include "pbs/raster/simd_clones.hpp"

#include <algorithm>
#include <cassert>

namespace pbs::flip {
namespace {

// acc[x] += w·(a[x] + b[x] − 2·centre[x]) or w·(b[x] − a[x]), by shape. Each pixel sums its taps in
// the same order whichever SIMD width runs, so every clone gives the same bits.
PBS_CLONE_INLINE void accumulateTap(KernelShape shape, float w, const float* a, const float* b, const float* centre,
                                    float* acc, std::uint32_t width) {
  if (shape == KernelShape::slope) {
    for (std::uint32_t x = 0; x < width; ++x) acc[x] += w * (b[x] - a[x]);
  } else {
    for (std::uint32_t x = 0; x < width; ++x) acc[x] += w * (a[x] + b[x] - 2.0f * centre[x]);
  }
}

PBS_CLONE_INLINE void startSum(KernelShape shape, const float* centre, float* acc, std::uint32_t width) {
  if (shape == KernelShape::smoothing)
    std::copy(centre, centre + width, acc);
  else
    std::fill(acc, acc + width, 0.0f);
}

}  // namespace

PaddedRow::PaddedRow(std::uint32_t width, std::uint32_t padding)
    : width(width), padding(padding), values(std::size_t(width) + 2 * std::size_t(padding)) {}

void PaddedRow::assign(const float* row) {
  if (width == 0) return;
  std::fill(values.begin(), values.begin() + padding, row[0]);
  std::copy(row, row + width, values.begin() + padding);
  std::fill(values.begin() + padding + width, values.end(), row[width - 1]);
}

PBS_AVX2_CLONES
void filterDown(const Plane& plane, std::uint32_t y, const HalfKernel& kernel, float* out) {
  const std::uint32_t width = plane.width;
  const float* centre = plane.row(y);
  startSum(kernel.shape, centre, out, width);
  const std::uint32_t last = plane.height - 1;
  for (std::uint32_t k = 1; k <= kernel.radius(); ++k) {
    const float* above = plane.row(y >= k ? y - k : 0);
    const float* below = plane.row(last - y >= k ? y + k : last);
    accumulateTap(kernel.shape, kernel.weights[k - 1], above, below, centre, out, width);
  }
}

PBS_AVX2_CLONES
void filterAlong(const PaddedRow& row, const HalfKernel& kernel, float* out) {
  assert(row.padding >= kernel.radius());
  const float* centre = row.begin();
  startSum(kernel.shape, centre, out, row.width);
  for (std::uint32_t k = 1; k <= kernel.radius(); ++k)
    accumulateTap(kernel.shape, kernel.weights[k - 1], centre - k, centre + k, centre, out, row.width);
}

}  // namespace pbs::flip
