// Surface area of a node's subtree: the A of the blue-noise measure ρ(k) (NOTES.md).
#pragma once

#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/scene.hpp"

#include <cstdint>

namespace pbs {

// The summed area of every triangle of every mesh instance in `node`'s subtree, each through its
// hierarchy.world transform (so a hierarchy rooted in a node's own frame gives the area in that frame).
// Degenerate triangles add 0. Instances under a similarity transform (rotation × uniform scale) reuse
// the mesh's own area, so a billion instanced triangles cost one pass over each distinct mesh.
double subtreeSurfaceArea(const Scene& scene, const Hierarchy& hierarchy, std::uint32_t node);

}  // namespace pbs
