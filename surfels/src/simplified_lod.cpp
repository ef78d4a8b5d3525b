// renderSimplifiedLod: traverseLod's surfel draws swapped for the simplified scene's subtree triangles.
#include "pbs/surfels/simplified_lod.hpp"

#include "elapsed.hpp"
#include "pbs/scene/scene_draws.hpp"

namespace pbs {

using detail::Clock;
using detail::secondsSince;

LodStats renderSimplifiedLod(const Scene& scene, const Scene& simplified, const Hierarchy& hierarchy,
                             const SceneSurfels& surfels, const Camera& camera, Framebuffer& framebuffer,
                             const LodOptions& options) {
  LodStats stats;
  const auto traverseStart = Clock::now();
  LodOptions noBand = options;
  noBand.band = 0.0;
  noBand.descendWhereRaysCheaper = false;  // the simplified meshes stand in for the surfels, rasterized
  const LodDraws draws = traverseLod(scene, hierarchy, surfels, camera, noBand);
  std::vector<std::uint32_t> small;
  for (const LodDraws::Surfels& draw : draws.surfels) {
    const std::vector<std::uint32_t> nodes = subtreeNodes(simplified, draw.node);
    small.insert(small.end(), nodes.begin(), nodes.end());
  }
  stats.triangles = draws.triangles;
  for (std::uint32_t node : small)
    if (const std::int32_t mesh = simplified.nodes[node].mesh; mesh >= 0)
      stats.triangles += simplified.meshes[std::size_t(mesh)].triangleCount();
  stats.traverseSeconds = secondsSince(traverseStart);

  const auto rasterStart = Clock::now();
  const TriangleOptions triangles{.cullBackFaces = false};  // as renderLod: open meshes show both sides
  drawNodeTriangles(scene, hierarchy, draws.geometryNodes, camera, framebuffer, triangles);
  drawNodeTriangles(simplified, hierarchy, small, camera, framebuffer, triangles);
  stats.rasterSeconds = secondsSince(rasterStart);

  stats.nodesGeometry = draws.geometryNodes.size();
  stats.nodesSurfels = draws.surfels.size();
  return stats;
}

}  // namespace pbs
