// Which nodes of a scene get a surfel array: those whose subtree is complex enough (paper, Sec. 2).
#pragma once

#include "pbs/scene/hierarchy.hpp"

#include <cstdint>
#include <vector>

namespace pbs {

// Nodes whose subtree holds more than `minTriangles` triangles (instances counted), in preorder.
// A scene with none needs no surfels at all.
std::vector<std::uint32_t> nodesNeedingSurfels(const Hierarchy& hierarchy, std::uint64_t minTriangles);

}  // namespace pbs
