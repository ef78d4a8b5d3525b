// Bottom-level BVHs of the Embree casters: watertight triangle BVHs over each mesh, built side by side.
#include "embree_meshes.hpp"

#include <tbb/parallel_for.h>

#include <cmath>
#include <cstring>

namespace pbs {
namespace {

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
  rtcCommitScene(scene.get());
  return scene;
}

}  // namespace

EmbreeMeshes makeEmbreeMeshes(const Scene& scene) {
  EmbreeMeshes meshes;
  meshes.allocations = std::make_shared<EmbreeAllocations>();
  meshes.device = makeEmbreeDevice(*meshes.allocations);
  meshes.scenes.resize(scene.meshes.size());
  return meshes;
}

EmbreeMeshes shareEmbreeMeshes(const EmbreeMeshes& meshes) {
  EmbreeMeshes shared;
  shared.allocations = meshes.allocations;
  shared.device = shareEmbreeDevice(meshes.device.get());
  shared.scenes.reserve(meshes.scenes.size());
  for (const EmbreeSceneHandle& scene : meshes.scenes) shared.scenes.push_back(shareEmbreeScene(scene.get()));
  return shared;
}

std::vector<std::uint32_t> rayInstanceNodes(const Scene& scene, const Hierarchy& hierarchy,
                                            std::span<const std::uint32_t> nodes) {
  std::vector<std::uint32_t> result;
  for (std::uint32_t node : nodes) {
    const std::int32_t mesh = scene.nodes[node].mesh;
    if (mesh >= 0 && scene.meshes[std::size_t(mesh)].triangleCount() > 0 && drawableTransform(hierarchy.world[node]))
      result.push_back(node);
  }
  return result;
}

MeshBuilds buildMeshScenes(EmbreeMeshes& meshes, const Scene& scene, std::span<const std::uint32_t> nodes) {
  std::vector<std::uint32_t> missing;
  std::vector<char> listed(scene.meshes.size(), 0);
  MeshBuilds builds;
  for (std::uint32_t node : nodes) {
    const auto mesh = std::uint32_t(scene.nodes[node].mesh);
    if (meshes.scenes[mesh] || listed[mesh]) continue;
    listed[mesh] = 1;
    missing.push_back(mesh);
    builds.triangles += scene.meshes[mesh].triangleCount();
  }
  builds.meshes = std::uint32_t(missing.size());
  // Each build is itself parallel; building them side by side also keeps the cores busy for scenes of
  // many small meshes. Embree allows concurrent commits of different scenes.
  RTCDevice device = meshes.device.get();
  tbb::parallel_for(std::size_t(0), missing.size(), [&](std::size_t i) {
    meshes.scenes[missing[i]] = buildMeshScene(device, scene.meshes[missing[i]]);
  });
  return builds;
}

}  // namespace pbs
