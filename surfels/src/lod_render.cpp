// renderLod: the traversal's geometry through the triangle rasterizer, its prefixes as blended splats or
// as nearest-wins points shrunk where surfels are seen edge-on.
#include "pbs/surfels/lod_render.hpp"

#include "elapsed.hpp"
#include "pbs/raster/blended_splats.hpp"
#include "pbs/raster/points.hpp"
#include "pbs/raster/value_names.hpp"
#include "pbs/surfels/frame_cost.hpp"
#include "pbs/surfels/lod_geometry.hpp"

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pbs {
namespace {

using detail::Clock;
using detail::secondsSince;

constexpr ValueNames<SplatMode, 2> kSplatNames{{{{SplatMode::Nearest, "nearest"}, {SplatMode::Blend, "blend"}}}};

// The unit direction from the eye toward the node's centre (one direction per node: the node is small on
// screen when it draws surfels), in world space.
glm::vec3 viewTowardNode(const SplatArray& splats, const glm::dmat4& world, const Camera& camera) {
  const glm::dmat4 worldFromEye = glm::inverse(camera.view);
  const glm::dvec3 toNode = camera.isOrthographic() ? glm::dvec3(worldFromEye * glm::dvec4(0.0, 0.0, -1.0, 0.0))
                                                    : glm::dvec3(world * glm::dvec4(splats.box.center(), 1.0)) -
                                                          glm::dvec3(worldFromEye * glm::dvec4(0.0, 0.0, 0.0, 1.0));
  const double length = glm::length(toNode);
  return length > 0.0 ? glm::vec3(toNode / length) : glm::vec3(0.0f, 0.0f, -1.0f);
}

// The cosine to the eye below which an array's surfels are not drawn: the options' limit, or none for an
// open sheet, whose surfels seen from one side sample the surface seen from the other (kOpenSheetShare).
float cullCosineOf(const SplatArray& splats, const LodOptions& options) {
  return splats.openSheet ? -1.0f : options.backFaceCosine;
}

// Nearest mode's per-surfel size factors: 0 for a surfel facing away (cosine to the eye below the array's
// limit, cullCosineOf), else max(|cos θ|, minSizeFactor) so that silhouettes stay sharp (paper, Sec. 3).
void sizeFactors(const SplatArray& splats, std::uint32_t count, const glm::dmat4& world, const Camera& camera,
                 const LodOptions& options, std::vector<float>& factors) {
  const glm::vec3 view = viewTowardNode(splats, world, camera);
  const glm::mat3 normalFromObject(glm::inverseTranspose(glm::dmat3(world)));
  const float cull = cullCosineOf(splats, options);
  factors.resize(count);
  for (std::uint32_t i = 0; i < count; ++i) {
    const glm::vec3 n = normalFromObject * splats.normals[i];
    const float norm = glm::length(n);
    const float toEye = norm > 0.0f ? -glm::dot(n, view) / norm : 1.0f;
    factors[i] = toEye < cull ? 0.0f : std::max(std::abs(toEye), options.minSizeFactor);
  }
}

glm::dmat4 objectFrame(const Hierarchy& hierarchy, const LodDraws::Surfels& draw, const SplatArray& splats) {
  return glm::translate(hierarchy.world[draw.node], splats.box.center());
}

void drawNearest(const Hierarchy& hierarchy, const SceneSurfels& surfels, const LodDraws& draws, const Camera& camera,
                 Framebuffer& framebuffer, const LodOptions& options) {
  std::vector<std::vector<float>> factors(draws.surfels.size());
  tbb::parallel_for(std::size_t(0), draws.surfels.size(), [&](std::size_t d) {
    const LodDraws::Surfels& draw = draws.surfels[d];
    sizeFactors(surfels.arrays[draw.array], draw.count, hierarchy.world[draw.node], camera, options, factors[d]);
  });
  const bool fixedSize = options.pointSize > 0.0f;
  bool subPixel = fixedSize && options.pointSize < 1.0f;
  std::vector<PointSet> sets;
  sets.reserve(draws.surfels.size());
  for (std::size_t d = 0; d < draws.surfels.size(); ++d) {
    const LodDraws::Surfels& draw = draws.surfels[d];
    const SplatArray& splats = surfels.arrays[draw.array];
    const auto pointSize = float(fixedSize ? options.pointSize : draw.pointSize);
    subPixel |= !fixedSize && pointSize < 1.0f;
    sets.push_back(PointSet{.positions = std::span(splats.positions).first(draw.count),
                            .normals = std::span(splats.normals).first(draw.count),
                            .colors = std::span(splats.colors).first(draw.count),
                            .sizeFactors = factors[d],
                            .worldFromObject = objectFrame(hierarchy, draw, splats),
                            .pointSize = pointSize,
                            .nodeId = draw.node,
                            .instanceId = draw.array});
  }
  drawPoints(framebuffer, camera, sets, PointOptions{.subPixel = subPixel});
}

void drawBlended(const Hierarchy& hierarchy, const SceneSurfels& surfels, const LodDraws& draws, const Camera& camera,
                 Framebuffer& framebuffer, const LodOptions& options) {
  std::vector<SurfelSplatSet> sets;
  sets.reserve(draws.surfels.size());
  for (const LodDraws::Surfels& draw : draws.surfels) {
    const SplatArray& splats = surfels.arrays[draw.array];
    sets.push_back(SurfelSplatSet{.positions = std::span(splats.positions).first(draw.count),
                                  .normals = std::span(splats.normals).first(draw.count),
                                  .colors = std::span(splats.colors).first(draw.count),
                                  .worldFromObject = objectFrame(hierarchy, draw, splats),
                                  .radius = float(draw.radius),
                                  .area = float(kSurfelAreaPerSpacing2 * draw.radius * draw.radius),
                                  .backFaceCosine = cullCosineOf(splats, options),
                                  .nodeId = draw.node,
                                  .instanceId = draw.array});
  }
  drawBlendedSplats(framebuffer, camera, sets, BlendOptions{.coverageGain = options.coverageGain});
}

}  // namespace

std::optional<SplatMode> splatModeFromName(std::string_view name) { return kSplatNames.parse(name); }
const char* splatModeName(SplatMode mode) { return kSplatNames.name(mode).data(); }

LodDraws traverseLodForDrawer(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels,
                              const Camera& camera, const LodOptions& options, const EmbreeNodeCaster* rays) {
  LodOptions thresholdOnly = options;
  thresholdOnly.descendWhereRaysCheaper = false;
  if (!options.descendWhereRaysCheaper || !rays) return traverseLod(scene, hierarchy, surfels, camera, thresholdOnly);
  LodDraws draws = traverseLod(scene, hierarchy, surfels, camera, options);
  // With the rasterizer named, raysCheaperAbove descended nowhere, and its price is per triangle: the thresholds' cut.
  if (options.geometry == GeometryDrawer::Raster) return draws;
  // A budget chooses its cut by cost, not by the thresholds the near rule shrinks.
  const bool nearRule = options.budget.limit == 0.0 && options.raysNearShare < 1.0;
  if (options.geometry == GeometryDrawer::Rays && !nearRule) return draws;
  const auto rasterChosen = [&](const GeometryWork& work) {
    return options.geometry == GeometryDrawer::Auto &&
           chooseGeometryDrawer(work, options.frameCosts, options.bvhBuildFrames) == GeometryDrawer::Raster;
  };
  const GeometryWork work = geometryWork(scene, hierarchy, draws.geometryNodes, camera, rays);
  if (rasterChosen(work)) return traverseLod(scene, hierarchy, surfels, camera, thresholdOnly);
  if (!nearRule) return draws;
  const double scale =
      nearFrameDescentScale(nearFrameShare(hierarchy, surfels, camera, draws, work.boxPixels), options.raysNearShare);
  if (scale >= 1.0) return draws;
  LodOptions near = options;
  near.descentScale = scale;
  LodDraws nearDraws = traverseLod(scene, hierarchy, surfels, camera, near);
  if (rasterChosen(geometryWork(scene, hierarchy, nearDraws.geometryNodes, camera, rays)))
    return traverseLod(scene, hierarchy, surfels, camera, thresholdOnly);
  return nearDraws;
}

double nearFrameShare(const Hierarchy& hierarchy, const SceneSurfels& surfels, const Camera& camera,
                      const LodDraws& draws, double geometryBoxPixels) {
  double splats = 0.0;
  for (const LodDraws::Surfels& draw : draws.surfels)
    splats += splatPixels(camera, hierarchy.world[draw.node], surfels.arrays[draw.array], draw);
  const double all = geometryBoxPixels + splats;
  return all > 0.0 ? geometryBoxPixels / all : 0.0;
}

double nearFrameDescentScale(double share, double raysNearShare) {
  if (!(share > raysNearShare)) return 1.0;  // NaN too
  return std::clamp(1.0 - (share - raysNearShare) / kNearFrameRamp, 0.0, 1.0);
}

LodStats renderLod(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels, const Camera& camera,
                   Framebuffer& framebuffer, const LodOptions& options, EmbreeNodeCaster* rays) {
  const auto traverseStart = Clock::now();
  const LodDraws draws = traverseLodForDrawer(scene, hierarchy, surfels, camera, options, rays);
  const double traverseSeconds = secondsSince(traverseStart);
  LodStats stats = drawLod(scene, hierarchy, surfels, draws, camera, framebuffer, options, rays);
  stats.traverseSeconds = traverseSeconds;
  return stats;
}

LodStats drawLod(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels, const LodDraws& draws,
                 const Camera& camera, Framebuffer& framebuffer, const LodOptions& options, EmbreeNodeCaster* rays) {
  LodStats stats;
  for (const LodDraws::Surfels& draw : draws.surfels)
    if (surfels.arrays[draw.array].loaded() < draw.count)
      throw std::logic_error("renderLod: array " + std::to_string(draw.array) + " draws " + std::to_string(draw.count) +
                             " surfels of which " + std::to_string(surfels.arrays[draw.array].loaded()) +
                             " are loaded (SurfelCache::load first)");

  const auto rasterStart = Clock::now();
  const GeometryPass geometry = drawLodGeometry(scene, hierarchy, draws.geometryNodes, camera, framebuffer,
                                                options.geometry, rays, options.frameCosts, options.bvhBuildFrames);
  // A framebuffer with the coverage channel is a blended frame's: every pixel of it is written, splats or not.
  if (options.splat == SplatMode::Blend && framebuffer.has(kChannelCoverage))
    drawBlended(hierarchy, surfels, draws, camera, framebuffer, options);
  else if (!draws.surfels.empty())
    drawNearest(hierarchy, surfels, draws, camera, framebuffer, options);
  stats.rasterSeconds = secondsSince(rasterStart);

  stats.triangles = draws.triangles;
  stats.surfels = draws.surfelCount;
  stats.nodesGeometry = draws.geometryNodes.size();
  stats.nodesSurfels = draws.surfels.size();
  stats.geometryPixels = geometry.work.boxPixels;
  stats.geometryRayPixels = geometry.work.boxRayPixels;
  stats.trianglesOnPixels = geometry.work.trianglesOnPixels;
  stats.nodesWeighed = draws.nodesWeighed;
  for (const LodDraws::Surfels& draw : draws.surfels)
    stats.surfelPixels += splatPixels(camera, hierarchy.world[draw.node], surfels.arrays[draw.array], draw);
  stats.geometryDrawer = geometry.drawer;
  stats.geometrySeconds = geometry.seconds;
  stats.bvhBuildSeconds = geometry.bvhBuildSeconds;
  return stats;
}

}  // namespace pbs
