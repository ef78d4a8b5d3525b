// Drawn point sizes, per block and their maximum over a set.
#include "points_sizes.hpp"

#include "points_splat.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>

namespace pbs::points {

void drawnSizes(const PointSet& set, float smallest, std::size_t first, std::size_t count, float* sizes) {
  if (set.sizeFactors.empty()) {
    std::fill_n(sizes, count, splatSize(set.pointSize, smallest));
    return;
  }
  for (std::size_t i = 0; i < count; ++i) sizes[i] = splatSize(set.pointSize * set.sizeFactors[first + i], smallest);
}

float largestDrawnSize(const PointSet& set, float smallest) {
  if (set.positions.empty()) return 0.0f;
  if (set.sizeFactors.empty()) return splatSize(set.pointSize, smallest);
  // A maximum does not depend on how the range is split, so the result is the same for any thread count.
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, set.sizeFactors.size(), 1 << 16), 0.0f,
      [&](const tbb::blocked_range<std::size_t>& range, float largest) {
        for (std::size_t i = range.begin(); i != range.end(); ++i)
          largest = std::max(largest, splatSize(set.pointSize * set.sizeFactors[i], smallest));
        return largest;
      },
      [](float a, float b) { return std::max(a, b); });
}

}  // namespace pbs::points
