// describeNode, rhoCurve and captureViewsPng: the scene's and the file's facts about one node, measured the
// way `pbs analyze` and `pbs capture` measure them.
#include "node_inspection.hpp"

#include "../png_writer.hpp"

#include <pbs/evaluation/contact_sheet.hpp>
#include <pbs/evaluation/ordering_analysis.hpp>
#include <pbs/scene/mesh_closure.hpp>
#include <pbs/scene/scene_draws.hpp>
#include <pbs/surfels/capture.hpp>
#include <pbs/surfels/surfelize.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace pbs::cli {
namespace {

std::uint32_t arrayOf(const FrameScene& scene, std::uint32_t node) {
  if (!scene.surfels) return kNoSurfels;
  const SceneSurfels& surfels = scene.surfels->surfels();
  return node < surfels.arrayOfNode.size() ? surfels.arrayOfNode[node] : kNoSurfels;
}

}  // namespace

void requireNode(const FrameScene& scene, std::uint32_t node) {
  const std::size_t nodes = scene.loaded.scene.nodes.size();
  if (node >= nodes) throw std::invalid_argument("node: the scene has " + std::to_string(nodes) + " nodes");
}

nlohmann::json describeNode(const FrameScene& scene, std::uint32_t node) {
  requireNode(scene, node);
  const Scene& graph = scene.loaded.scene;
  const Hierarchy& hierarchy = scene.loaded.hierarchy;
  std::vector<std::string> path;
  for (std::int32_t at = std::int32_t(node); at >= 0; at = hierarchy.parent[std::size_t(at)])
    path.push_back(graph.nodes[std::size_t(at)].name);
  std::reverse(path.begin(), path.end());
  const std::int32_t mesh = graph.nodes[node].mesh;
  nlohmann::json description = {{"node", node},
                                {"name", graph.nodes[node].name},
                                {"path", path},
                                {"triangles", mesh >= 0 ? graph.meshes[std::size_t(mesh)].triangleCount() : 0},
                                {"subtree_triangles", hierarchy.subtreeTriangles[node]},
                                {"children", graph.nodes[node].children.size()}};
  const Bounds& box = hierarchy.worldBounds[node];
  if (!box.empty()) {
    const glm::dvec3 center = box.center();
    description["center"] = {center.x, center.y, center.z};
    description["radius"] = 0.5 * glm::length(box.size());
  }
  if (const std::uint32_t array = arrayOf(scene, node); array != kNoSurfels) {
    const SurfelArrayInfo& info = scene.surfels->arrays()[array];
    description["array"] = {{"index", array},          {"surfels", info.count},          {"coverage", info.coverage},
                            {"packing", info.packing}, {"packing_end", info.packingEnd}, {"area", info.area}};
  }
  return description;
}

nlohmann::json rhoCurve(FrameScene& scene, std::uint32_t node, std::size_t points) {
  requireNode(scene, node);
  const std::uint32_t array = arrayOf(scene, node);
  if (array == kNoSurfels) throw std::invalid_argument("node " + std::to_string(node) + ": no surfel array");
  const SurfelArrayInfo& info = scene.surfels->arrays()[array];
  scene.surfels->loadPrefix(array, info.count);
  const SplatArray& splats = scene.surfels->surfels().arrays[array];
  // The positions the ordering saw (the two sides of a thin surface apart), as `pbs analyze` measures.
  std::vector<Surfel> surfels(splats.loaded());
  for (std::size_t i = 0; i < surfels.size(); ++i)
    surfels[i] = Surfel{splats.positions[i], splats.normals[i], splats.colors[i]};
  const std::vector<glm::vec3> positions = orderingPositions(surfels);
  std::vector<std::uint32_t> order(positions.size());
  std::iota(order.begin(), order.end(), 0u);
  MeasuredOrdering measured;
  measured.area = info.area;
  measureOrdering(measured, positions, order);
  nlohmann::json curve = {{"k", nlohmann::json::array()},
                          {"rho", nlohmann::json::array()},
                          {"rho_min", measured.summary.rhoMin},
                          {"rho_mean", measured.summary.rhoMean}};
  const std::size_t count = positions.size();
  std::size_t last = 0;
  for (std::size_t i = 0; i < points && count >= 2; ++i) {
    // Log-spaced from k = 2 to the whole array, each k once.
    const auto k = std::size_t(std::llround(2.0 * std::pow(double(count) / 2.0, double(i) / double(points - 1))));
    if (k <= last || k > count) continue;
    last = k;
    curve["k"].push_back(k);
    curve["rho"].push_back(measured.rho(k));
  }
  return curve;
}

std::vector<std::uint8_t> captureViewsPng(FrameScene& scene, std::uint32_t node, std::uint32_t resolution) {
  requireNode(scene, node);
  const Scene& graph = scene.loaded.scene;
  LazyMeshes::Lease meshes;
  if (scene.meshes) meshes = scene.meshes->requireDrawnBy(subtreeNodes(graph, node));
  // Each view centred in a square tile: views of a flat box are not square.
  std::vector<std::vector<std::uint8_t>> tiles;
  CaptureOptions options;
  options.resolution = resolution;
  const std::vector<MeshClosure> closures = meshClosures(graph);  // as surfelize draws each mesh: those leased here
  options.meshClosures = closures;
  options.onView = [&](std::uint32_t, const Camera& camera, const Framebuffer& gbuffer) {
    std::vector<std::uint8_t> tile(std::size_t(resolution) * resolution * 4, 0);
    const std::uint32_t left = (resolution - std::min(resolution, camera.width)) / 2;
    const std::uint32_t top = (resolution - std::min(resolution, camera.height)) / 2;
    for (std::uint32_t y = 0; y < std::min(resolution, camera.height); ++y)
      for (std::uint32_t x = 0; x < std::min(resolution, camera.width); ++x) {
        const std::size_t pixel = std::size_t(y) * camera.width + x;
        if (!gbuffer.covered(pixel)) continue;
        const glm::u8vec4 color = gbuffer.color[pixel];
        std::uint8_t* out = &tile[(std::size_t(top + y) * resolution + left + x) * 4];
        out[0] = color.r, out[1] = color.g, out[2] = color.b, out[3] = 255;
      }
    tiles.push_back(std::move(tile));
  };
  captureNode(graph, scene.loaded.hierarchy, node, options);
  if (tiles.empty()) throw std::invalid_argument("node " + std::to_string(node) + ": draws nothing to capture");
  const std::uint32_t columns = std::min<std::uint32_t>(4, std::uint32_t(tiles.size()));
  const std::uint32_t rows = (std::uint32_t(tiles.size()) + columns - 1) / columns;
  while (tiles.size() < std::size_t(rows) * columns) tiles.emplace_back(std::size_t(resolution) * resolution * 4, 0);
  const std::vector<std::span<const std::uint8_t>> spans(tiles.begin(), tiles.end());
  const std::uint8_t white[3] = {255, 255, 255};
  const std::vector<std::uint8_t> sheet = contactSheet(resolution, resolution, columns, spans, white);
  return encodePng8(columns * resolution, rows * resolution, 3, sheet.data());
}

}  // namespace pbs::cli
