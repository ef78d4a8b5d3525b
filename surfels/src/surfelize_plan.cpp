// planSurfelArrays: nodes above the threshold, grouped into shared arrays by subtree class, and what
// each array's capture draws.
#include "surfelize_plan.hpp"

#include "pbs/scene/subtree_classes.hpp"
#include "pbs/surfels/surfel_nodes.hpp"

#include <algorithm>

namespace pbs::detail {
namespace {

// What `node`'s capture from its children would draw: each child array at `arrayLength` splats, the
// triangles of children without one; and whether any child has an array.
struct ChildDrawing {
  std::uint64_t primitives = 0;
  bool anyArray = false;
};
ChildDrawing childDrawing(const Scene& scene, const Hierarchy& hierarchy, std::uint32_t node,
                          const std::vector<std::uint32_t>& arrayOfNode, std::uint64_t arrayLength) {
  ChildDrawing drawing;
  for (std::uint32_t child : scene.nodes[node].children) {
    const bool hasArray = arrayOfNode[child] != kNoSurfels;
    drawing.anyArray |= hasArray;
    drawing.primitives += hasArray ? arrayLength : hierarchy.subtreeTriangles[child];
  }
  return drawing;
}

// Whether a capture draws the children's surfels (see CaptureSource) rather than the subtree's triangles.
bool capturesFromChildren(CaptureSource source, std::uint64_t subtreeTriangles, const ChildDrawing& children) {
  if (source == CaptureSource::Triangles || !children.anyArray) return false;
  return source == CaptureSource::ChildSurfels ||
         double(subtreeTriangles) > kAutoChildSurfelRatio * double(children.primitives);
}

}  // namespace

SurfelPlan planSurfelArrays(const Scene& scene, const Hierarchy& hierarchy, const SurfelizeOptions& options) {
  SurfelPlan plan;
  plan.nodes = nodesNeedingSurfels(hierarchy, options.file.threshold);
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

  plan.childArrays.resize(arrays);
  plan.fromChildren.resize(arrays);
  plan.primitivesDrawn.resize(arrays);
  for (std::uint32_t a = 0; a < arrays; ++a) {
    const std::uint32_t node = plan.representative[a];
    const ChildDrawing drawing = childDrawing(scene, hierarchy, node, plan.arrayOfNode, options.file.maxSurfels);
    plan.fromChildren[a] = capturesFromChildren(options.source, hierarchy.subtreeTriangles[node], drawing);
    plan.primitivesDrawn[a] = plan.fromChildren[a] ? drawing.primitives : hierarchy.subtreeTriangles[node];
    if (!plan.fromChildren[a]) continue;
    std::vector<std::uint32_t>& children = plan.childArrays[a];
    for (std::uint32_t child : scene.nodes[node].children)
      if (plan.arrayOfNode[child] != kNoSurfels) children.push_back(plan.arrayOfNode[child]);
    std::sort(children.begin(), children.end());
    children.erase(std::unique(children.begin(), children.end()), children.end());
  }
  return plan;
}

}  // namespace pbs::detail
