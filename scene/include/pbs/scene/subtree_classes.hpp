// Which nodes carry identical subtrees: the unit of sharing for everything computed in a node's own
// frame (surfel arrays above all), generalizing "a mesh used by many nodes is computed once".
#pragma once

#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/scene.hpp"

#include <cstdint>
#include <vector>

namespace pbs {

// One class number per node. Two nodes share a class exactly when their subtrees are the same in the
// nodes' own frames: the same mesh (or none), and the same number of children whose local transforms
// are bit-identical and whose classes are equal, in the same order. Each node's own local transform
// does not count (it places the subtree, it is not part of it), so every instance of a mesh with no
// children is one class. Classes are numbered 0, 1, … in hierarchy.preorder order of first
// appearance, so the numbering depends only on the scene. Exact comparison: no hash collisions.
std::vector<std::uint32_t> subtreeClasses(const Scene& scene, const Hierarchy& hierarchy);

}  // namespace pbs
