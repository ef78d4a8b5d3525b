// Which nodes of a scene get a surfel array (paper, Sec. 2), and the stable names arrays are stored under.
#pragma once

#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/scene.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace pbs {

// Nodes whose subtree holds more than `minTriangles` triangles (instances counted), in preorder.
// A scene with none needs no surfels at all.
std::vector<std::uint32_t> nodesNeedingSurfels(const Hierarchy& hierarchy, std::uint64_t minTriangles);

// The node's stable path: "/" + its root's position in Scene::roots, then "/" + its position among its
// parent's children for every step down, e.g. "/0/3/1". It depends only on the graph's shape, never on
// names (which may repeat or be empty) or node numbering, so a re-exported scene keeps its paths.
std::string nodePath(const Scene& scene, const Hierarchy& hierarchy, std::uint32_t node);

// nodePath of every node, built in one pass from the roots (a node's path extends its parent's), so
// scenes with very wide nodes cost no sibling searches. Indexed by node.
std::vector<std::string> nodePaths(const Scene& scene, const Hierarchy& hierarchy);

}  // namespace pbs
