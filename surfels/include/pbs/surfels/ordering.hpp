// Progressive orderings of point sets: permutations whose every prefix is evenly spread (blue noise).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace pbs {

// The orderings' random stream, splitmix64: the same draws on every compiler and standard library
// (unlike std::uniform_*_distribution). Public so tests and benchmarks can reproduce or reuse it.
class OrderRng {
 public:
  explicit OrderRng(std::uint64_t seed) : state_(seed) {}

  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

  // A value in [0, n) by multiply-shift (bias below 2^-32 for n < 2^32, and no rejection loop).
  std::uint64_t below(std::uint64_t n) {
    return static_cast<std::uint64_t>((static_cast<unsigned __int128>(next()) * n) >> 64);
  }

  // A double in [0, 1) from the top 53 bits.
  double unit() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

 private:
  std::uint64_t state_;
};

// Every function returns distinct indices into `points`, at most `max` of them, and depends only on
// its arguments: the random draws come from an OrderRng seeded with `seed`, and ties between
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
