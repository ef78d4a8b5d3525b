// Selection of the nodes complex enough to be replaced by surfels, and their stable paths.
#include "pbs/surfels/surfel_nodes.hpp"

#include <algorithm>

namespace pbs {

std::vector<std::uint32_t> nodesNeedingSurfels(const Hierarchy& hierarchy, std::uint64_t minTriangles) {
  std::vector<std::uint32_t> nodes;
  for (std::uint32_t n : hierarchy.preorder)
    if (hierarchy.subtreeTriangles[n] > minTriangles) nodes.push_back(n);
  return nodes;
}

std::string nodePath(const Scene& scene, const Hierarchy& hierarchy, std::uint32_t node) {
  std::vector<std::size_t> steps;
  for (std::int64_t n = node; n >= 0; n = hierarchy.parent[std::size_t(n)]) {
    const std::int32_t parent = hierarchy.parent[std::size_t(n)];
    const std::vector<std::uint32_t>& siblings = parent >= 0 ? scene.nodes[std::size_t(parent)].children : scene.roots;
    steps.push_back(std::size_t(std::find(siblings.begin(), siblings.end(), std::uint32_t(n)) - siblings.begin()));
  }
  std::string path;
  for (auto step = steps.rbegin(); step != steps.rend(); ++step) path.append("/").append(std::to_string(*step));
  return path;
}

std::vector<std::string> nodePaths(const Scene& scene, const Hierarchy& hierarchy) {
  std::vector<std::string> paths(scene.nodes.size());
  for (std::size_t r = 0; r < scene.roots.size(); ++r) paths[scene.roots[r]].append("/").append(std::to_string(r));
  for (std::uint32_t n : hierarchy.preorder) {  // parents before children
    const std::vector<std::uint32_t>& children = scene.nodes[n].children;
    for (std::size_t c = 0; c < children.size(); ++c)
      paths[children[c]].append(paths[n]).append("/").append(std::to_string(c));
  }
  return paths;
}

}  // namespace pbs
