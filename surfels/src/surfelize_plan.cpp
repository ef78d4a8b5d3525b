// planSurfelArrays: nodes above the threshold, grouped into shared arrays by subtree class.
#include "surfelize_plan.hpp"

#include "pbs/scene/subtree_classes.hpp"
#include "pbs/surfels/surfel_nodes.hpp"

#include <algorithm>

namespace pbs::detail {

SurfelPlan planSurfelArrays(const Scene& scene, const Hierarchy& hierarchy, std::uint64_t threshold) {
  SurfelPlan plan;
  plan.nodes = nodesNeedingSurfels(hierarchy, threshold);
  plan.arrayOfNode.assign(scene.nodes.size(), kNoSurfels);
  if (plan.nodes.empty()) return plan;  // nothing to share, nothing to classify

  std::vector<std::uint32_t> nodeHeight(scene.nodes.size(), 0);
  for (auto it = hierarchy.preorder.rbegin(); it != hierarchy.preorder.rend(); ++it)
    for (std::uint32_t child : scene.nodes[*it].children)
      nodeHeight[*it] = std::max(nodeHeight[*it], nodeHeight[child] + 1);

  const std::vector<std::uint32_t> classes = subtreeClasses(scene, hierarchy);
  std::vector<std::uint32_t> arrayOfClass(classes.empty() ? 0 : *std::max_element(classes.begin(), classes.end()) + 1,
                                          kNoSurfels);
  for (std::uint32_t node : plan.nodes) {
    std::uint32_t& array = arrayOfClass[classes[node]];
    if (array == kNoSurfels) {
      array = std::uint32_t(plan.representative.size());
      plan.representative.push_back(node);
      plan.height.push_back(nodeHeight[node]);
    }
    plan.arrayOfNode[node] = array;
  }
  return plan;
}

}  // namespace pbs::detail
