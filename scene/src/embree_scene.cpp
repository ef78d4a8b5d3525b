// EmbreeScene: every mesh BVH its nodes need built up front, one top level over all its instances.
#include "embree_scene_impl.hpp"

#include <numeric>

namespace pbs {
namespace {

std::vector<std::uint32_t> allNodes(const Scene& scene) {
  std::vector<std::uint32_t> nodes(scene.nodes.size());
  std::iota(nodes.begin(), nodes.end(), 0u);
  return nodes;
}

}  // namespace

EmbreeScene::EmbreeScene(const Scene& scene, const Hierarchy& hierarchy)
    : EmbreeScene(scene, hierarchy, allNodes(scene)) {}

EmbreeScene::EmbreeScene(const Scene& scene, const Hierarchy& hierarchy, std::span<const std::uint32_t> nodes)
    : impl_(std::make_unique<Impl>()) {
  Impl& impl = *impl_;
  impl.materials = makeSceneMaterials(scene);
  impl.meshes = makeEmbreeMeshes(scene);
  const std::vector<std::uint32_t> instanceNodes = rayInstanceNodes(scene, hierarchy, nodes);
  buildMeshScenes(impl.meshes, scene, instanceNodes);
  impl.instances = makeEmbreeInstances(impl.meshes, scene, hierarchy, impl.materials, instanceNodes,
                                       nodesCenter(hierarchy, nodes));
}

EmbreeScene::~EmbreeScene() = default;
EmbreeScene::EmbreeScene(EmbreeScene&&) noexcept = default;
EmbreeScene& EmbreeScene::operator=(EmbreeScene&&) noexcept = default;

void EmbreeScene::render(const Camera& camera, Framebuffer& framebuffer) const {
  castRays(impl_->instances, camera, framebuffer);
}

const glm::dvec3& EmbreeScene::origin() const { return impl_->instances.origin; }

}  // namespace pbs
