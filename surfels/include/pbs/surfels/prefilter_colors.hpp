// Pre-filtered surfel colours: a surfel of an ordered array stands for the neighbourhood of the captured
// surface that its place in the order leaves to it, so it carries that neighbourhood's average colour
// instead of the one pixel it was captured from. A prefix then shows the surface's colours low-passed to
// its own spacing rather than aliased point samples of them.
#pragma once

#include "pbs/surfels/surfel.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace pbs {

// How surfelize colours the surfels it keeps (the numbers are stored in .surfels headers): the colour
// of the pixel each was captured from, or the filtered colour of prefilteredColors.
enum class SurfelColors : std::uint32_t { Pixel = 0, Prefiltered = 1 };

// "pixel", "prefiltered".
std::string_view surfelColorsName(SurfelColors colors);
std::optional<SurfelColors> parseSurfelColors(std::string_view name);

// Per entry i of `order` (indices into `points`), its insertion distance d(i): the distance from
// points[order[i]] to the nearest of points[order[0 .. i)], +inf for i = 0. Any order works (farthest,
// dart, random, or one given by hand); a repeated point gets 0. Distances are the square roots of the
// float squared distances the orderings measure. Costs about one grid query per entry.
// Throws std::invalid_argument for an index out of range, or (as the orderings do) for points that
// are not finite or span more than 1e18.
std::vector<float> insertionDistances(std::span<const glm::vec3> points, std::span<const std::uint32_t> order);

// Per entry i of `order` (indices into `candidates`), the RGBA colour averaged over every candidate c
// with |c − p|² ≤ d(i)² (p = candidates[order[i]].position, d = insertionDistances of the positions,
// both squared in float), weighted by the Gaussian exp(−|c − p|² / (2σ²)) of σ = d(i) / 2, and
// rounded to nearest. So the first surfel (d = +inf) gets the plain mean of all candidates, and a
// surfel placed on top of another (d = 0) the mean of the candidates at exactly its position. The
// candidate itself always counts, so there is always weight.
// Precision: the weights are a polynomial within about 1e-6 of the Gaussian, summed in float over at
// most 256 candidates at a time and then in double, so a channel is the exact mean correctly rounded
// unless that mean lies within about 1e-3 of a half.
// Cost: candidates are found in a uniform grid, so it is about the sum of the neighbourhood sizes,
// which on a surface is N · ln(order.size()) for N candidates, not N · order.size(); the sums run in
// vector lanes (AVX2 where the CPU has it). Each surfel's sums run in a fixed candidate order and lane
// assignment, so the result is bit-identical for any thread count and either instruction set.
// Throws as insertionDistances does, naming prefilteredColors.
std::vector<glm::u8vec4> prefilteredColors(std::span<const Surfel> candidates, std::span<const std::uint32_t> order);

// The same with candidate i seen at positions[i] instead of its own position (the ordering's positions,
// orderingPositions in surfelize.hpp), its colour still candidates[i]'s. Throws std::invalid_argument when
// the two differ in length.
std::vector<glm::u8vec4> prefilteredColors(std::span<const glm::vec3> positions, std::span<const Surfel> candidates,
                                           std::span<const std::uint32_t> order);

}  // namespace pbs
