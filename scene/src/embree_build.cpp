// Builds an EmbreeScene: one bottom-level BVH per used mesh, instanced by every node that draws it.
#include "embree_scene_impl.hpp"

#include <tbb/parallel_for.h>

#include <cmath>
#include <cstring>
#include <numeric>

namespace pbs {
namespace {

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

// A singular transform flattens the mesh into zero-area triangles, which cover no pixel (as in the
// rasterizer); Embree could not invert it.
bool drawableTransform(const glm::dmat4& world) {
  const double det = glm::determinant(glm::dmat3(world));
  return std::isfinite(det) && det != 0.0;
}

EmbreeSceneHandle buildMeshScene(RTCDevice device, const Mesh& mesh) {
  EmbreeGeometry geometry = makeEmbreeGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  // Copied into an Embree buffer, which Embree pads for its 16-byte loads past the last vertex; a
  // std::vector of vec3 has no such padding.
  void* vertices = rtcSetNewGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                           sizeof(glm::vec3), mesh.positions.size());
  std::memcpy(vertices, mesh.positions.data(), mesh.positions.size() * sizeof(glm::vec3));
  rtcSetSharedGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.indices.data(), 0,
                             3 * sizeof(std::uint32_t), mesh.triangleCount());
  rtcCommitGeometry(geometry.get());
  // Robust: watertight triangle tests, so no ray slips through an edge two triangles share.
  EmbreeSceneHandle scene = makeEmbreeScene(device, RTC_SCENE_FLAG_ROBUST);
  rtcAttachGeometry(scene.get(), geometry.get());
  return scene;
}

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

EmbreeScene::EmbreeScene(const Scene& scene, const Hierarchy& hierarchy)
    : EmbreeScene(scene, hierarchy, allNodes(scene)) {}

EmbreeScene::EmbreeScene(const Scene& scene, const Hierarchy& hierarchy, std::span<const std::uint32_t> nodes)
    : impl_(std::make_unique<Impl>()) {
  Impl& impl = *impl_;
  impl.materials = makeSceneMaterials(scene);
  impl.origin = nodesCenter(hierarchy, nodes);
  impl.device = makeEmbreeDevice();
  RTCDevice device = impl.device.get();

  std::vector<std::uint32_t> drawnNodes;
  std::vector<char> meshUsed(scene.meshes.size(), 0);
  for (std::uint32_t node : nodes) {
    const std::int32_t mesh = scene.nodes[node].mesh;
    if (mesh < 0 || scene.meshes[std::size_t(mesh)].triangleCount() == 0 || !drawableTransform(hierarchy.world[node]))
      continue;
    drawnNodes.push_back(node);
    meshUsed[std::size_t(mesh)] = 1;
  }

  // Each bottom-level build is itself parallel; building them side by side also keeps the cores busy
  // for scenes of many small meshes. Embree allows concurrent commits of different scenes.
  impl.meshScenes.resize(scene.meshes.size());
  tbb::parallel_for(std::size_t(0), scene.meshes.size(), [&](std::size_t mesh) {
    if (!meshUsed[mesh]) return;
    impl.meshScenes[mesh] = buildMeshScene(device, scene.meshes[mesh]);
    rtcCommitScene(impl.meshScenes[mesh].get());
  });

  impl.top = makeEmbreeScene(device, RTC_SCENE_FLAG_NONE);
  impl.instances.reserve(drawnNodes.size());
  for (std::uint32_t node : drawnNodes) {
    const auto mesh = std::uint32_t(scene.nodes[node].mesh);
    const glm::dmat4& world = hierarchy.world[node];
    // The instance's id in the top-level scene is its index in `instances`, which hits report.
    attachInstance(device, impl.top.get(), unsigned(impl.instances.size()), impl.meshScenes[mesh].get(), world,
                   impl.origin);
    impl.instances.push_back(ShadedInstance{&scene.meshes[mesh], impl.materials.forMesh(scene.meshes[mesh]), &world,
                                            node, mesh});
  }
  rtcCommitScene(impl.top.get());
}

EmbreeScene::~EmbreeScene() = default;
EmbreeScene::EmbreeScene(EmbreeScene&&) noexcept = default;
EmbreeScene& EmbreeScene::operator=(EmbreeScene&&) noexcept = default;

const glm::dvec3& EmbreeScene::origin() const { return impl_->origin; }

}  // namespace pbs
