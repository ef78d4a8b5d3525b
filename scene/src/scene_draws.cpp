// Turns the scene model into TriangleDraws, culls instances outside the view and draws the rest.
#include "pbs/scene/scene_draws.hpp"

#include "pbs/raster/raster_limits.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace pbs {

SceneMaterials makeSceneMaterials(const Scene& scene) {
  SceneMaterials result;
  result.textured.reserve(scene.materials.size());
  result.untextured.reserve(scene.materials.size());
  for (const Material& material : scene.materials) {
    const Texture* texture =
        material.baseColorTexture >= 0 ? &scene.textures[std::size_t(material.baseColorTexture)] : nullptr;
    result.textured.push_back({material.baseColorFactor, texture});
    result.untextured.push_back({material.baseColorFactor, nullptr});
  }
  return result;
}

Bounds instanceWorldBounds(const Scene& scene, const Hierarchy& hierarchy, std::uint32_t node) {
  return scene.nodes[node].mesh < 0 ? Bounds{} : hierarchy.instanceBounds[node];
}

void drawSceneTriangles(const Scene& scene, const Hierarchy& hierarchy, const Camera& camera, Framebuffer& framebuffer,
                        const TriangleOptions& options) {
  std::vector<std::uint32_t> nodes(scene.nodes.size());
  std::iota(nodes.begin(), nodes.end(), 0u);
  drawNodeTriangles(scene, hierarchy, nodes, camera, framebuffer, options);
}

std::vector<std::uint32_t> subtreeNodes(const Scene& scene, std::uint32_t root) {
  std::vector<std::uint32_t> result;
  std::vector<std::uint32_t> stack{root};
  while (!stack.empty()) {
    const std::uint32_t node = stack.back();
    stack.pop_back();
    result.push_back(node);
    // Pushed in reverse so children come out in their listed order.
    const std::vector<std::uint32_t>& children = scene.nodes[node].children;
    stack.insert(stack.end(), children.rbegin(), children.rend());
  }
  return result;
}

PixelRect holePixels(const Camera& camera, const glm::dmat4& clipFromObject, const Bounds& hole) {
  const PixelRect window{0, 0, std::int32_t(camera.width) - 1, std::int32_t(camera.height) - 1};
  glm::dvec2 low(std::numeric_limits<double>::infinity()), high(-std::numeric_limits<double>::infinity());
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 p(corner & 1 ? hole.max.x : hole.min.x, corner & 2 ? hole.max.y : hole.min.y,
                       corner & 4 ? hole.max.z : hole.min.z);
    const glm::dvec4 clip = clipFromObject * glm::dvec4(p, 1.0);
    if (!(clip.w > 0.0) || !std::isfinite(clip.x) || !std::isfinite(clip.y)) return window;
    const glm::dvec3 at = windowFromClip(camera, clip);
    low = glm::min(low, glm::dvec2(at));
    high = glm::max(high, glm::dvec2(at));
  }
  const auto pixel = [](double x) { return std::int32_t(std::clamp(std::floor(x), -2.0, double(kMaxViewportSize))); };
  return {pixel(low.x) - 1, pixel(low.y) - 1, pixel(high.x) + 1, pixel(high.y) + 1};
}

void drawNodeTriangles(const Scene& scene, const Hierarchy& hierarchy, std::span<const std::uint32_t> nodes,
                       const Camera& camera, Framebuffer& framebuffer, const TriangleOptions& options,
                       std::span<const MeshClosure> meshClosures) {
  const SceneMaterials materials = makeSceneMaterials(scene);
  std::vector<TriangleDraw> draws;
  std::vector<std::vector<PixelRect>> holes;  // per draw
  const BoxProjection boxes(camera);
  for (std::uint32_t node : nodes) {
    const std::int32_t meshIndex = scene.nodes[node].mesh;
    if (meshIndex < 0 || boxes.outside(instanceWorldBounds(scene, hierarchy, node))) continue;
    const Mesh& mesh = scene.meshes[std::size_t(meshIndex)];
    TriangleDraw draw;
    draw.positions = mesh.positions;
    draw.normals = mesh.normals;
    draw.uvs = mesh.uvs;
    draw.indices = mesh.indices;
    draw.parts = mesh.parts;
    draw.materials = materials.forMesh(mesh);
    draw.worldFromObject = hierarchy.world[node];
    draw.nodeId = node;
    draw.instanceId = std::uint32_t(meshIndex);
    std::vector<PixelRect>& drawHoles = holes.emplace_back();
    if (std::size_t(meshIndex) < meshClosures.size()) {
      const MeshClosure& closure = meshClosures[std::size_t(meshIndex)];
      draw.sides = visibleSides(closure.facing);
      const glm::dmat4 clipFromObject = camera.clipFromWorld() * draw.worldFromObject;
      for (const Bounds& hole : closure.holes) drawHoles.push_back(holePixels(camera, clipFromObject, hole));
    }
    draws.push_back(draw);
  }
  for (std::size_t d = 0; d < draws.size(); ++d) draws[d].otherSidesWithin = holes[d];
  drawTriangles(framebuffer, camera, draws, options);
}

}  // namespace pbs
