// Median by radix selection: non-negative floats order as their bit patterns do, so the k-th smallest is
// found from a histogram of the high 16 bits and then one of the low 16 bits inside the chosen bin —
// two parallel counting passes instead of a serial nth_element (a sixth of FLIP's time on two threads).
#include "flip_median.hpp"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <bit>
#include <cstdint>
#include <vector>

namespace pbs::flip {
namespace {

constexpr std::size_t kBins = std::size_t(1) << 16;

std::uint32_t bitsOf(float value) { return std::bit_cast<std::uint32_t>(value); }

// Counts of `values` by the 16-bit key keyOf returns (values for which it returns kBins are skipped).
// Counts are integers: the sum over threads does not depend on how the work was shared out.
template <typename KeyOf>
std::vector<std::uint64_t> histogram(std::span<const float> values, KeyOf keyOf) {
  tbb::combinable<std::vector<std::uint64_t>> partial([] { return std::vector<std::uint64_t>(kBins + 1, 0); });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, values.size(), std::size_t(1) << 16),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      std::vector<std::uint64_t>& counts = partial.local();
                      for (std::size_t i = range.begin(); i != range.end(); ++i) ++counts[keyOf(bitsOf(values[i]))];
                    });
  std::vector<std::uint64_t> total(kBins, 0);
  partial.combine_each([&](const std::vector<std::uint64_t>& counts) {
    for (std::size_t bin = 0; bin < kBins; ++bin) total[bin] += counts[bin];
  });
  return total;
}

// The bin holding the k-th smallest counted value; `k` becomes its rank within that bin.
std::uint32_t binOfRank(const std::vector<std::uint64_t>& counts, std::uint64_t& k) {
  std::uint32_t bin = 0;
  while (k >= counts[bin]) k -= counts[bin++];
  return bin;
}

float kthSmallest(std::span<const float> values, const std::vector<std::uint64_t>& highCounts, std::uint64_t k) {
  const std::uint32_t high = binOfRank(highCounts, k);
  const std::vector<std::uint64_t> lowCounts = histogram(
      values, [high](std::uint32_t bits) { return (bits >> 16) == high ? bits & 0xffffu : std::uint32_t(kBins); });
  const std::uint32_t low = binOfRank(lowCounts, k);
  return std::bit_cast<float>((high << 16) | low);
}

}  // namespace

double medianOfNonNegative(std::span<const float> values) {
  if (values.empty()) return 0.0;
  const std::vector<std::uint64_t> highCounts = histogram(values, [](std::uint32_t bits) { return bits >> 16; });
  const std::uint64_t middle = values.size() / 2;
  const double upper = kthSmallest(values, highCounts, middle);
  if (values.size() % 2 == 1) return upper;
  return 0.5 * (double(kthSmallest(values, highCounts, middle - 1)) + upper);
}

}  // namespace pbs::flip
