// Every point's nearest other point at once (the packing values of surfelize, the metrics).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace pbs {

// For each of `points`, the squared distance to its nearest other point (+inf for a lone point), to the
// bit as NearestPointGrid::nearestSquared gives it: the same float expression, and min is exact. Entries
// at the same position count as distinct points (distance 0). Throws std::invalid_argument as
// orderableBox does (naming `who` and, with `names`, the caller's name of the point).
std::vector<float> allNearestSquared(std::span<const glm::vec3> points, const char* who,
                                     std::span<const std::uint32_t> names = {});

}  // namespace pbs
