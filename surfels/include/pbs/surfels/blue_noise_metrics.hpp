// Blue-noise measures of an ordered point prefix: minimal spacing, relative radius ρ, mean neighbour distance.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace pbs {

// Like the orderings (ordering.hpp), the measures throw std::invalid_argument for non-finite points,
// points spanning more than 1e18, or an order index past the points; coincident points give d_min 0.
// They read only the points they measure (those of the order, or of its first `count` entries): the
// others may be anything.

// Entry k-1 is d_min(k): the smallest distance between two of the first k ordered points, computed as
// the running minimum of each new point's distance to its predecessors. Entry 0 is +infinity (no pair).
std::vector<double> prefixMinDistances(std::span<const glm::vec3> points, std::span<const std::uint32_t> order);

// ρ(k) = d_min / sqrt(2A / (√3 k)): the spacing relative to hexagonal packing of k points on area A.
// 0 when k is 0 or the area is not positive (0, negative or NaN): never a division by zero.
double relativeRadius(double minDistance, std::size_t k, double area);

// The mean, over the first `count` ordered points, of each one's distance to its nearest other point
// among them (the "packing" input of the renderer); 0 for fewer than two points. An index the order holds
// twice is two points at one place.
double meanNearestNeighbourDistance(std::span<const glm::vec3> points, std::span<const std::uint32_t> order,
                                    std::size_t count);

struct BlueNoiseSummary {
  double rhoMin = 0.0;   // min ρ(k) over k ≥ 100 (k ≥ 2 for shorter orders)
  double rhoMean = 0.0;  // mean ρ(k) over 32 log-spaced k from that first k to the full length
};

// Both ρ summaries of `order` on a surface of area `area`; zeros for orders shorter than two and for
// an area that is not positive.
BlueNoiseSummary summarizeBlueNoise(std::span<const glm::vec3> points, std::span<const std::uint32_t> order,
                                    double area);

}  // namespace pbs
