// Turns the scene model into TriangleDraws, culls instances outside the view and draws the rest.
#include "pbs/scene/scene_draws.hpp"

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

void drawNodeTriangles(const Scene& scene, const Hierarchy& hierarchy, std::span<const std::uint32_t> nodes,
                       const Camera& camera, Framebuffer& framebuffer, const TriangleOptions& options,
                       std::span<const MeshFacing> meshFacings) {
  const SceneMaterials materials = makeSceneMaterials(scene);
  std::vector<TriangleDraw> draws;
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
    if (std::size_t(meshIndex) < meshFacings.size()) draw.sides = visibleSides(meshFacings[std::size_t(meshIndex)]);
    draws.push_back(draw);
  }
  drawTriangles(framebuffer, camera, draws, options);
}

}  // namespace pbs
