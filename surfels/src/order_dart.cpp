// orderDart: the paper's best-candidate dart throwing over a pool with O(1) removal.
#include "order_nearest_grid.hpp"

#include <pbs/surfels/ordering.hpp>

#include <algorithm>
#include <limits>
#include <numeric>

namespace pbs {

namespace {

// The pool of unchosen points; removal swaps the last entry into the hole, so positions change.
struct Pool {
  std::vector<std::uint32_t> indices;

  void removeAt(std::size_t position) {
    indices[position] = indices.back();
    indices.pop_back();
  }
};

}  // namespace

std::vector<std::uint32_t> orderDart(std::span<const glm::vec3> points, std::uint32_t max, std::uint64_t seed,
                                     std::uint32_t candidates) {
  std::vector<std::uint32_t> order;
  if (points.empty() || max == 0) return order;
  Pool pool;
  pool.indices.resize(points.size());
  std::iota(pool.indices.begin(), pool.indices.end(), 0u);
  NearestPointGrid chosen(points, "orderDart");
  SeededRandom rng(seed);
  const auto choose = [&](std::size_t position) {
    order.push_back(pool.indices[position]);
    chosen.insert(pool.indices[position]);
  };

  const std::size_t first = rng.below(pool.indices.size());
  choose(first);
  pool.removeAt(first);
  const std::uint32_t draws = std::max(1u, candidates);
  while (order.size() < max && !pool.indices.empty()) {
    std::size_t farPos = 0, nearPos = 0;
    float farD = -1.0f, nearD = std::numeric_limits<float>::infinity();
    for (std::uint32_t c = 0; c < draws; ++c) {
      const std::size_t pos = rng.below(pool.indices.size());
      const std::uint32_t index = pool.indices[pos];
      const float d = chosen.nearestSquared(points[index]);
      if (d > farD || (d == farD && index < pool.indices[farPos])) farD = d, farPos = pos;
      if (d < nearD || (d == nearD && index < pool.indices[nearPos])) nearD = d, nearPos = pos;
    }
    choose(farPos);
    // Remove the higher position first so the lower one is not moved by the swap.
    pool.removeAt(std::max(farPos, nearPos));
    if (nearPos != farPos) pool.removeAt(std::min(farPos, nearPos));
  }
  return order;
}

}  // namespace pbs
