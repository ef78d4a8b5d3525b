// Which arrays a scene needs and which node each is captured for: the bookkeeping half of surfelize.
#pragma once

#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/scene.hpp"
#include "pbs/surfels/scene_surfels.hpp"

#include <cstdint>
#include <vector>

namespace pbs::detail {

struct SurfelPlan {
  std::vector<std::uint32_t> nodes;           // nodes above the threshold, in preorder
  std::vector<std::uint32_t> arrayOfNode;     // per scene node: its array, or kNoSurfels
  std::vector<std::uint32_t> representative;  // per array: the node it is captured for (first in preorder)
};

// Nodes above `threshold` subtree triangles; nodes of one subtree class share an array. Arrays are
// numbered children first (in reverse preorder of their first node there): an array's children's
// arrays come before it, so making them in index order never waits on a later one, and a file
// written in index order as they finish holds little back.
SurfelPlan planSurfelArrays(const Scene& scene, const Hierarchy& hierarchy, std::uint64_t threshold);

}  // namespace pbs::detail
