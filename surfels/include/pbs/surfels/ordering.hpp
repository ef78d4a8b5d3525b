// Progressive orderings of point sets: permutations whose every prefix is evenly spread (blue noise).
#pragma once

#include "pbs/raster/seeded_random.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace pbs {

// Every function returns distinct indices into `points`, at most `max` of them, and depends only on
// its arguments: the random draws come from a SeededRandom seeded with `seed`, and ties between
// equal distances go to the lower index.

// The first `max` entries of a uniformly random permutation (the baseline with no spacing at all).
std::vector<std::uint32_t> orderRandom(std::span<const glm::vec3> points, std::uint32_t max, std::uint64_t seed);

// Best-candidate dart throwing as the paper describes it: one random point, then rounds that draw
// `candidates` random pool points (with replacement), append the one farthest from every chosen point,
// drop the nearest one from the pool for good and return the rest. Because of the drops the result can
// be shorter than min(max, points.size()).
std::vector<std::uint32_t> orderDart(std::span<const glm::vec3> points, std::uint32_t max, std::uint64_t seed,
                                     std::uint32_t candidates = 200);

// The exact greedy (farthest-point) permutation: a random first point, then always the pool point
// farthest from every chosen one. Each prefix is within a factor 2 of the best spacing for its size.
std::vector<std::uint32_t> orderFarthest(std::span<const glm::vec3> points, std::uint32_t max, std::uint64_t seed);

}  // namespace pbs
