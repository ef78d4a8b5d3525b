// EmbreeNodeCaster: mesh BVHs built on first need and kept, a top level per set of instances.
#include "pbs/scene/embree_node_caster.hpp"

#include "embree_instances.hpp"
#include "embree_scene_impl.hpp"

#include <chrono>

namespace pbs {

struct EmbreeNodeCaster::Impl {
  const Scene* scene = nullptr;
  const Hierarchy* hierarchy = nullptr;
  SceneMaterials materials;  // points into the Scene's textures
  // Declared in creation order so they are released in reverse: instances, meshes, then the device.
  EmbreeMeshes meshes;
  EmbreeInstances instances;            // over topNodes; no top scene before the first render
  std::vector<std::uint32_t> topNodes;  // kept while renders ask for the same (a still camera, samples)
  std::vector<char> drawn;              // per mesh: drawnBefore
  // Every top level's frame is centred on the whole scene, by EmbreeScene's own rule over all nodes: each instance
  // then sees the very rays `--mode embree` casts, so the geometry a frame draws here is its image to the bit, and
  // the frame does not move as the view's nodes change.
  glm::dvec3 origin{0.0};
};

EmbreeNodeCaster::EmbreeNodeCaster(const Scene& scene, const Hierarchy& hierarchy) : impl_(std::make_unique<Impl>()) {
  impl_->scene = &scene;
  impl_->hierarchy = &hierarchy;
  impl_->materials = makeSceneMaterials(scene);
  impl_->meshes = makeEmbreeMeshes(scene);
  impl_->drawn.assign(scene.meshes.size(), 0);
  impl_->origin = nodesCenter(hierarchy, allNodes(scene));
}

EmbreeNodeCaster::EmbreeNodeCaster(const Scene& scene, const Hierarchy& hierarchy, const EmbreeScene& prebuilt)
    : impl_(std::make_unique<Impl>()) {
  impl_->scene = &scene;
  impl_->hierarchy = &hierarchy;
  impl_->materials = makeSceneMaterials(scene);
  impl_->meshes = shareEmbreeMeshes(prebuilt.impl_->meshes);
  impl_->drawn.assign(scene.meshes.size(), 0);
  impl_->origin = nodesCenter(hierarchy, allNodes(scene));
}

EmbreeNodeCaster::~EmbreeNodeCaster() = default;
EmbreeNodeCaster::EmbreeNodeCaster(EmbreeNodeCaster&&) noexcept = default;
EmbreeNodeCaster& EmbreeNodeCaster::operator=(EmbreeNodeCaster&&) noexcept = default;

namespace {

// The instances of `nodes` a render casts at: those inside the camera's clip volume.
std::vector<std::uint32_t> instancesInView(const Scene& scene, const Hierarchy& hierarchy, const Camera& camera,
                                           std::span<const std::uint32_t> nodes) {
  std::vector<std::uint32_t> inView;
  const BoxProjection boxes(camera);
  for (std::uint32_t node : rayInstanceNodes(scene, hierarchy, nodes))
    if (!boxes.outside(instanceWorldBounds(scene, hierarchy, node))) inView.push_back(node);
  return inView;
}

void noteMeshes(const Scene& scene, std::span<const std::uint32_t> nodes, std::vector<char>& drawn) {
  for (std::uint32_t node : nodes) drawn[std::size_t(scene.nodes[node].mesh)] = 1;
}

}  // namespace

void EmbreeNodeCaster::noteDrawn(const Camera& camera, std::span<const std::uint32_t> nodes) {
  noteMeshes(*impl_->scene, instancesInView(*impl_->scene, *impl_->hierarchy, camera, nodes), impl_->drawn);
}

EmbreeBuilds EmbreeNodeCaster::render(const Camera& camera, std::span<const std::uint32_t> nodes,
                                      Framebuffer& framebuffer) {
  Impl& impl = *impl_;
  const Scene& scene = *impl.scene;
  const Hierarchy& hierarchy = *impl.hierarchy;
  const std::vector<std::uint32_t> inView = instancesInView(scene, hierarchy, camera, nodes);
  noteMeshes(scene, inView, impl.drawn);

  const auto start = std::chrono::steady_clock::now();
  const MeshBuilds built = buildMeshScenes(impl.meshes, scene, inView);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const EmbreeBuilds builds{built.meshes, built.triangles, built.meshes > 0 ? seconds : 0.0};

  if (!impl.instances.top || inView != impl.topNodes) {
    impl.instances = makeEmbreeInstances(impl.meshes, scene, hierarchy, impl.materials, inView, impl.origin);
    impl.topNodes = inView;
  }
  castRays(impl.instances, camera, framebuffer);
  return builds;
}

bool EmbreeNodeCaster::built(std::uint32_t mesh) const { return bool(impl_->meshes.scenes.at(mesh)); }

bool EmbreeNodeCaster::drawnBefore(std::uint32_t mesh) const { return bool(impl_->drawn.at(mesh)); }

void EmbreeNodeCaster::forget(std::uint32_t mesh) {
  impl_->instances = EmbreeInstances{};
  impl_->topNodes.clear();
  impl_->meshes.scenes.at(mesh) = EmbreeSceneHandle{};
}

}  // namespace pbs
