// Selection of the nodes complex enough to be replaced by surfels.
#include "pbs/surfels/surfel_nodes.hpp"

namespace pbs {

std::vector<std::uint32_t> nodesNeedingSurfels(const Hierarchy& hierarchy, std::uint64_t minTriangles) {
  std::vector<std::uint32_t> nodes;
  for (std::uint32_t n : hierarchy.preorder)
    if (hierarchy.subtreeTriangles[n] > minTriangles) nodes.push_back(n);
  return nodes;
}

}  // namespace pbs
