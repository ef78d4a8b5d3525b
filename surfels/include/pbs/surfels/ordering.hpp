// Progressive orderings of point sets: permutations whose every prefix is evenly spread (blue noise).
#pragma once

#include "pbs/raster/seeded_random.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace pbs {

// Every function returns distinct indices into `points`, at most `max` of them, and depends only on
// its arguments: the random draws come from a SeededRandom seeded with `seed`, and ties between
// equal distances go to the lower index.
//
// Stiff inputs (tests/test_ordering_stiff.cpp), all defined, none quadratic in a degenerate way:
// - empty `points` or max 0: an empty order. One point: {0}. max above the pool: farthest and random
//   return a permutation of all points; dart stops when its pool runs dry (see orderDart).
// - coincident points: every distance ties at 0, so after the first point the rest follow in index
//   order (farthest takes that tail in one pass); d_min and ρ are 0. Spreads below float's smallest
//   normal number (~1e-38) count as coincident: their squared distances underflow to 0.
// - collinear, planar (zero thickness), clustered points: exact as anywhere else; farthest spends
//   O(cluster size) per chosen point when far-apart clusters each fit one cell of its grid.
// - distances are float squared distances, so scaling the points by a power of two gives the same
//   order; any other scale rounds the points and may swap near ties.
// - positions are float: 1e6 from the origin the step is 0.0625, so finer detail has already
//   collapsed into duplicates before ordering. Keep points relative to a nearby origin (surfels are).
// - non-finite coordinates, or points spanning more than 1e18 (squared distances would overflow):
//   orderFarthest and orderDart throw std::invalid_argument naming the point, before any work.
//   orderRandom never reads the positions and accepts them.

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

// The three orderings by name, for options and files (the numbers are stored in .surfels headers).
enum class SurfelOrdering : std::uint32_t { Farthest = 0, Dart = 1, Random = 2 };

// "farthest", "dart", "random".
std::string_view orderingName(SurfelOrdering ordering);
std::optional<SurfelOrdering> parseOrdering(std::string_view name);

// Dispatches to orderFarthest, orderDart (with its default candidate count) or orderRandom.
std::vector<std::uint32_t> orderPoints(SurfelOrdering ordering, std::span<const glm::vec3> points, std::uint32_t max,
                                       std::uint64_t seed);

}  // namespace pbs
