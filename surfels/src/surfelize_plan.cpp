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

  const std::vector<std::uint32_t> classes = subtreeClasses(scene, hierarchy);
  const std::size_t classCount = classes.empty() ? 0 : *std::max_element(classes.begin(), classes.end()) + 1;
  // Numbers: children first. Every node's descendants come before it in reverse preorder, and a node
  // of an array's class has children of its children's classes, so those are numbered sooner.
  std::vector<std::uint32_t> arrayOfClass(classCount, kNoSurfels);
  std::uint32_t arrays = 0;
  for (auto node = plan.nodes.rbegin(); node != plan.nodes.rend(); ++node)
    if (std::uint32_t& array = arrayOfClass[classes[*node]]; array == kNoSurfels) array = arrays++;
  // Representatives: the first node of each class in preorder (its path seeds the ordering).
  plan.representative.assign(arrays, kNoSurfels);
  for (std::uint32_t node : plan.nodes) {
    const std::uint32_t array = arrayOfClass[classes[node]];
    if (plan.representative[array] == kNoSurfels) plan.representative[array] = node;
    plan.arrayOfNode[node] = array;
  }
  return plan;
}

}  // namespace pbs::detail
