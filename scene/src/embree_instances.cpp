// Top-level Embree scenes: one instance per node, its transform made origin-relative in double.
#include "embree_instances.hpp"

#include <numeric>

namespace pbs {
namespace {

void attachInstance(RTCDevice device, RTCScene top, unsigned int id, RTCScene meshScene, const glm::dmat4& world,
                    const glm::dvec3& origin) {
  // Embree takes a float 3×4 (column-major) in its origin-relative frame; the translation is made
  // relative in double first.
  float transform[12];
  for (int column = 0; column < 3; ++column)
    for (int row = 0; row < 3; ++row) transform[column * 3 + row] = float(world[column][row]);
  for (int row = 0; row < 3; ++row) transform[9 + row] = float(world[3][row] - origin[row]);
  EmbreeGeometry instance = makeEmbreeGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(instance.get(), meshScene);
  rtcSetGeometryTransform(instance.get(), 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, transform);
  rtcCommitGeometry(instance.get());
  rtcAttachGeometryByID(top, instance.get(), id);
}

}  // namespace

// Every node's subtree box lies inside its root's, so over all nodes this is the scene's centre.
glm::dvec3 nodesCenter(const Hierarchy& hierarchy, std::span<const std::uint32_t> nodes) {
  Bounds bounds;
  for (std::uint32_t node : nodes) bounds.extend(hierarchy.worldBounds[node]);
  return bounds.empty() ? glm::dvec3(0.0) : bounds.center();
}

std::vector<std::uint32_t> allNodes(const Scene& scene) {
  std::vector<std::uint32_t> nodes(scene.nodes.size());
  std::iota(nodes.begin(), nodes.end(), 0u);
  return nodes;
}

EmbreeInstances makeEmbreeInstances(const EmbreeMeshes& meshes, const Scene& scene, const Hierarchy& hierarchy,
                                    const SceneMaterials& materials, std::span<const std::uint32_t> nodes,
                                    const glm::dvec3& origin) {
  EmbreeInstances instances;
  instances.origin = origin;
  RTCDevice device = meshes.device.get();
  instances.top = makeEmbreeScene(device, RTC_SCENE_FLAG_NONE);
  instances.shaded.reserve(nodes.size());
  for (std::uint32_t node : nodes) {
    const auto mesh = std::uint32_t(scene.nodes[node].mesh);
    const glm::dmat4& world = hierarchy.world[node];
    // The instance's id in the top-level scene is its index in `shaded`, which hits report.
    attachInstance(device, instances.top.get(), unsigned(instances.shaded.size()), meshes.scenes[mesh].get(), world,
                   origin);
    instances.shaded.push_back(
        ShadedInstance{&scene.meshes[mesh], materials.forMesh(scene.meshes[mesh]), &world, node, mesh});
  }
  rtcCommitScene(instances.top.get());
  std::vector<Bounds> boxes;
  boxes.reserve(nodes.size());
  for (std::uint32_t node : nodes) boxes.push_back(instanceWorldBounds(scene, hierarchy, node));
  instances.footprint = coveringBoxes(boxes);
  return instances;
}

}  // namespace pbs
