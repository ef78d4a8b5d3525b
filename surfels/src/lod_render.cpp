// renderLod: the traversal's geometry through the triangle rasterizer, its prefixes as point splats
// shrunk where surfels are seen edge-on.
#include "pbs/surfels/lod_render.hpp"

#include "elapsed.hpp"
#include "pbs/raster/points.hpp"
#include "pbs/raster/triangles.hpp"
#include "pbs/scene/scene_draws.hpp"
#include "pbs/surfels/lod_geometry.hpp"

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace pbs {
namespace {

using detail::Clock;
using detail::secondsSince;

// max(|cos θ|, minimum) per surfel of the prefix, θ between its world normal and the view direction
// toward the node (one direction per node: the node is small on screen when it draws surfels).
void edgeOnFactors(const SplatArray& splats, std::uint32_t count, const glm::dmat4& world, const Camera& camera,
                   float minimum, std::vector<float>& factors) {
  const glm::dmat4 eyeFromWorld = camera.view;
  const glm::dvec3 center(world * glm::dvec4(splats.box.center(), 1.0));
  glm::dvec3 toNode;
  if (camera.isOrthographic()) {
    toNode = glm::dvec3(glm::inverse(eyeFromWorld) * glm::dvec4(0.0, 0.0, -1.0, 0.0));
  } else {
    const glm::dvec3 eye(glm::inverse(eyeFromWorld) * glm::dvec4(0.0, 0.0, 0.0, 1.0));
    toNode = center - eye;
  }
  const double length = glm::length(toNode);
  const glm::vec3 view = length > 0.0 ? glm::vec3(toNode / length) : glm::vec3(0.0f, 0.0f, -1.0f);
  const glm::mat3 normalFromObject(glm::inverseTranspose(glm::dmat3(world)));
  factors.resize(count);
  for (std::uint32_t i = 0; i < count; ++i) {
    const glm::vec3 n = normalFromObject * splats.normals[i];
    const float norm = glm::length(n);
    const float cosine = norm > 0.0f ? std::abs(glm::dot(n, view)) / norm : 1.0f;
    factors[i] = std::max(cosine, minimum);
  }
}

}  // namespace

LodStats renderLod(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels, const Camera& camera,
                   Framebuffer& framebuffer, const LodOptions& options, EmbreeNodeCaster* rays) {
  LodStats stats;
  const auto traverseStart = Clock::now();
  const LodDraws draws = traverseLod(scene, hierarchy, surfels, camera, options);
  std::vector<std::vector<float>> factors(draws.surfels.size());
  const bool shrink = options.minSizeFactor < 1.0f;
  if (shrink)
    tbb::parallel_for(std::size_t(0), draws.surfels.size(), [&](std::size_t d) {
      const LodDraws::Surfels& draw = draws.surfels[d];
      edgeOnFactors(surfels.arrays[draw.array], draw.count, hierarchy.world[draw.node], camera, options.minSizeFactor,
                    factors[d]);
    });
  std::vector<PointSet> sets;
  sets.reserve(draws.surfels.size());
  for (std::size_t d = 0; d < draws.surfels.size(); ++d) {
    const LodDraws::Surfels& draw = draws.surfels[d];
    const SplatArray& splats = surfels.arrays[draw.array];
    sets.push_back(PointSet{.positions = std::span(splats.positions).first(draw.count),
                            .normals = std::span(splats.normals).first(draw.count),
                            .colors = std::span(splats.colors).first(draw.count),
                            .sizeFactors = shrink ? std::span<const float>(factors[d]) : std::span<const float>(),
                            .worldFromObject = glm::translate(hierarchy.world[draw.node], splats.box.center()),
                            .pointSize = options.pointSize,
                            .nodeId = draw.node,
                            .instanceId = draw.array});
  }
  stats.traverseSeconds = secondsSince(traverseStart);

  const auto rasterStart = Clock::now();
  const GeometryPass geometry =
      drawLodGeometry(scene, hierarchy, draws.geometryNodes, camera, framebuffer, options.geometry, rays);
  drawPoints(framebuffer, camera, sets, PointOptions{.subPixel = options.pointSize < 1.0f});
  stats.rasterSeconds = secondsSince(rasterStart);

  stats.triangles = draws.triangles;
  stats.surfels = draws.surfelCount;
  stats.nodesGeometry = draws.geometryNodes.size();
  stats.nodesSurfels = draws.surfels.size();
  stats.geometryDrawer = geometry.drawer;
  stats.geometrySeconds = geometry.seconds;
  stats.bvhBuildSeconds = geometry.bvhBuildSeconds;
  return stats;
}

}  // namespace pbs
