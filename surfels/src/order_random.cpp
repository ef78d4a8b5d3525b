// orderRandom: a prefix of a random permutation by a partial Fisher–Yates shuffle.
#include <pbs/surfels/ordering.hpp>

#include <algorithm>
#include <numeric>

namespace pbs {

std::vector<std::uint32_t> orderRandom(std::span<const glm::vec3> points, std::uint32_t max, std::uint64_t seed) {
  std::vector<std::uint32_t> indices(points.size());
  std::iota(indices.begin(), indices.end(), 0u);
  const std::size_t count = std::min<std::size_t>(max, indices.size());
  SeededRandom rng(seed);
  for (std::size_t i = 0; i < count; ++i) {
    std::swap(indices[i], indices[i + rng.below(indices.size() - i)]);
  }
  indices.resize(count);
  return indices;
}

}  // namespace pbs
