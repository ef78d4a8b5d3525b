// Which arrays a scene needs, which node each is captured for and what its capture draws: the
// bookkeeping half of surfelize, a pure function of the scene and the options.
#pragma once

#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/scene.hpp"
#include "pbs/surfels/scene_surfels.hpp"
#include "pbs/surfels/surfelize.hpp"

#include <cstdint>
#include <vector>

namespace pbs::detail {

struct SurfelPlan {
  std::vector<std::uint32_t> nodes;           // nodes above the threshold, in preorder
  std::vector<std::uint32_t> arrayOfNode;     // per scene node: its array, or kNoSurfels
  std::vector<std::uint32_t> representative;  // per array: the node it is captured for (first in preorder)
  // Per array: the distinct arrays of its representative's children, ascending, when its capture draws
  // them (CaptureSource), else none. Their indices are lower: an array needs only these made before it.
  std::vector<std::vector<std::uint32_t>> childArrays;
  std::vector<bool> fromChildren;  // per array: whether its capture draws its children's surfels
  // Per array: the triangles and splats its capture draws (child arrays counted at their full length).
  std::vector<std::uint64_t> primitivesDrawn;
};

// Nodes above options.file.threshold subtree triangles; nodes of one subtree class share an array.
// Arrays are numbered children first (in reverse preorder of their first node there): an array's
// children's arrays come before it, so making them in index order never waits on a later one, and a
// file written in index order as they finish holds little back. What each capture draws is decided
// here, before any array is made (children's arrays counted at their full length, options.file.maxSurfels),
// so which arrays need which is known up front: a shard of the plan knows what it must make.
SurfelPlan planSurfelArrays(const Scene& scene, const Hierarchy& hierarchy, const SurfelizeOptions& options);

}  // namespace pbs::detail
