// traverseLod: the runtime decisions of the paper's Sec. 3, one node at a time from the roots.
#include "pbs/surfels/lod_render.hpp"

#include "lod_budget.hpp"
#include "lod_scale.hpp"

#include "pbs/raster/projected_box.hpp"
#include "pbs/scene/scene_draws.hpp"

#include <algorithm>
#include <cmath>

namespace pbs {
namespace {

using lod::NodeScale;

class Traversal {
 public:
  Traversal(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels, const Camera& camera,
            const LodOptions& options)
      : scene_(scene), hierarchy_(hierarchy), surfels_(surfels), camera_(camera), boxes_(camera), options_(options) {}

  // `growth` in [0, 1] scales the surfel prefixes of this subtree: below 1 while an ancestor's
  // transition hands over to its descendants.
  void visit(std::uint32_t node, double growth) {
    const Bounds& box = hierarchy_.worldBounds[node];
    if (boxes_.outside(box)) return;
    const std::uint32_t array = node < surfels_.arrayOfNode.size() ? surfels_.arrayOfNode[node] : kNoSurfels;
    const double size = std::sqrt(boxes_.pixels(box));
    const NodeScale at =
        array != kNoSurfels ? lod::nodeScale(camera_, hierarchy_.world[node], surfels_.arrays[array]) : NodeScale{};
    const double threshold = array != kNoSurfels
                                 ? lod::descentThreshold(surfels_.arrays[array], at, size, hierarchy_, node, options_)
                                 : options_.threshold;
    const double upper = threshold * (1.0 + options_.band);
    if (array != kNoSurfels && size < upper) {
      // Inside the band the node's prefix first stays whole while the children grow in, then shrinks
      // away ("the prefix of one level decreases after the maximal prefix of the next is rendered").
      const double t = options_.band > 0.0 ? std::clamp((size - threshold) / (upper - threshold), 0.0, 1.0)
                                           : (size <= threshold ? 0.0 : 1.0);
      drawSurfels(node, array, at, size, growth * std::min(1.0, 2.0 * (1.0 - t)));
      if (t <= 0.0) return;
      descend(node, growth * std::min(1.0, 2.0 * t));
      return;
    }
    descend(node, growth);
  }

  // The node's array at full weight, sized by its projected size as if it were inside the threshold.
  void drawWhole(std::uint32_t node) {
    const std::uint32_t array = surfels_.arrayOfNode[node];
    const double size = std::sqrt(boxes_.pixels(hierarchy_.worldBounds[node]));
    drawSurfels(node, array, lod::nodeScale(camera_, hierarchy_.world[node], surfels_.arrays[array]), size, 1.0);
  }

  LodDraws draws;

 private:
  void descend(std::uint32_t node, double growth) {
    const std::int32_t mesh = scene_.nodes[node].mesh;
    if (mesh >= 0) {
      draws.geometryNodes.push_back(node);
      draws.triangles += scene_.meshes[std::size_t(mesh)].triangleCount();
    }
    for (std::uint32_t child : scene_.nodes[node].children) visit(child, growth);
  }

  void drawSurfels(std::uint32_t node, std::uint32_t array, const NodeScale& at, double size, double factor) {
    const SplatArray& splats = surfels_.arrays[array];
    const std::uint32_t full = prefixLength(splats, size, at.worldPixel, at.scale, options_);
    const auto count = std::uint32_t(std::lround(double(full) * factor));
    if (count == 0) return;
    draws.surfels.push_back(lod::prefixDraw(node, array, splats, at, full, count));
    draws.surfelCount += count;
  }

  const Scene& scene_;
  const Hierarchy& hierarchy_;
  const SceneSurfels& surfels_;
  const Camera& camera_;
  const BoxProjection boxes_;
  const LodOptions& options_;
};

}  // namespace

double prefixDemand(const SplatArray& array, double projectedSize, double worldPixel, double scale,
                    const LodOptions& options) {
  double count = 0.0;
  // Points sized from the prefix count surfels as the paper does for its reference point size.
  const bool fixedSize = options.pointSize > 0.0f;
  const double pointSize = fixedSize ? double(options.pointSize) : double(kReferencePointSize);
  if (options.prefixRule == PrefixRule::Coverage || !fixedSize) {
    const double relativeSize = pointSize / kReferencePointSize;
    count = projectedSize * projectedSize * array.coverage * options.overdraw / (relativeSize * relativeSize);
  } else {
    // The point radius in the node's own frame, where the packing value was measured.
    const double radius = pointSize * worldPixel / 2.0 / scale;
    count = radius > 0.0 ? array.packing / (radius * radius) : double(array.size());
  }
  return count;
}

std::uint32_t prefixLength(const SplatArray& array, double projectedSize, double worldPixel, double scale,
                           const LodOptions& options) {
  const double count = prefixDemand(array, projectedSize, worldPixel, scale, options);
  if (!(count > 0.0)) return 0;
  return std::uint32_t(std::min(std::round(count), double(array.size())));
}

LodDraws traverseLod(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels, const Camera& camera,
                     const LodOptions& options) {
  if (options.budget.limit > 0.0) return traverseWithBudget(scene, hierarchy, surfels, camera, options);
  Traversal traversal(scene, hierarchy, surfels, camera, options);
  for (std::uint32_t root : scene.roots) traversal.visit(root, 1.0);
  return std::move(traversal.draws);
}

std::optional<LodDraws::Surfels> wholeArrayDraw(const Scene& scene, const Hierarchy& hierarchy,
                                                const SceneSurfels& surfels, const Camera& camera,
                                                const LodOptions& options, std::uint32_t node) {
  if (node >= surfels.arrayOfNode.size() || surfels.arrayOfNode[node] == kNoSurfels) return std::nullopt;
  Traversal traversal(scene, hierarchy, surfels, camera, options);
  traversal.drawWhole(node);
  if (traversal.draws.surfels.empty()) return std::nullopt;
  return traversal.draws.surfels.front();
}

}  // namespace pbs
