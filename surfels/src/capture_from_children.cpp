// captureFromChildSurfels: children with arrays drawn as splats, everything else as triangles.
#include "capture_from_children.hpp"

#include "surfelize_plan.hpp"

#include "pbs/raster/points.hpp"
#include "pbs/scene/scene_draws.hpp"
#include "pbs/surfels/scene_surfels.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

namespace pbs::detail {
namespace {

double largestScale(const glm::dmat4& transform) {
  return std::max({glm::length(glm::dvec3(transform[0])), glm::length(glm::dvec3(transform[1])),
                   glm::length(glm::dvec3(transform[2]))});
}

}  // namespace

std::vector<std::uint32_t> childCaptureTriangleNodes(const Scene& scene, std::uint32_t node,
                                                     std::span<const std::uint32_t> arrayOfNode) {
  std::vector<std::uint32_t> nodes;
  if (scene.nodes[node].mesh >= 0) nodes.push_back(node);
  for (std::uint32_t child : scene.nodes[node].children) {
    if (arrayOfNode[child] != kNoSurfels) continue;
    const std::vector<std::uint32_t> below = subtreeNodes(scene, child);
    nodes.insert(nodes.end(), below.begin(), below.end());
  }
  return nodes;
}

CaptureResult captureFromChildSurfels(const Scene& scene, const Hierarchy& frame, std::uint32_t node,
                                      std::span<const SurfelArray> arrays, std::span<const std::uint32_t> arrayOfNode,
                                      const CaptureOptions& options) {
  // Splats a little wider than the spacing, so neighbours overlap instead of leaving pinholes.
  constexpr double kSplatOverlap = 1.25;
  constexpr float kMaxSplatPixels = 64.0f;

  const std::vector<std::uint32_t> triangleNodes = childCaptureTriangleNodes(scene, node, arrayOfNode);
  std::vector<std::uint32_t> splatChildren;
  for (std::uint32_t child : scene.nodes[node].children)
    if (arrayOfNode[child] != kNoSurfels) splatChildren.push_back(child);
  std::map<std::uint32_t, SplatArray> splats;  // one conversion per distinct array
  for (std::uint32_t child : splatChildren) {
    const std::uint32_t array = arrayOfNode[child];
    if (!splats.contains(array)) splats.emplace(array, splatArrayOf(arrays[array]));
  }

  return captureBox(frame.worldBounds[node], options, [&](const Camera& camera, Framebuffer& gbuffer) {
    drawNodeTriangles(scene, frame, triangleNodes, camera, gbuffer, TriangleOptions{.cullBackFaces = false},
                      options.meshClosures);
    const double pixel = 2.0 / (camera.projection[0][0] * camera.width);  // orthographic: world units per pixel
    std::vector<PointSet> sets;
    for (std::uint32_t child : splatChildren) {
      const std::uint32_t array = arrayOfNode[child];
      const SplatArray& s = splats.at(array);
      const glm::dmat4 transform = glm::translate(frame.world[child], arrays[array].box.center());
      const double size = kSplatOverlap * s.spacing(s.size()) * largestScale(frame.world[child]) / pixel;
      sets.push_back(PointSet{.positions = s.positions,
                              .normals = s.normals,
                              .colors = s.colors,
                              .worldFromObject = transform,
                              .pointSize = std::clamp(float(size), 1.0f, kMaxSplatPixels),
                              .nodeId = child});
    }
    drawPoints(gbuffer, camera, sets);
  });
}

}  // namespace pbs::detail
