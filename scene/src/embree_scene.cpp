// EmbreeScene: every mesh BVH its nodes need built up front, one top level over all its instances.
#include "embree_scene_impl.hpp"

#include <algorithm>

namespace pbs {
namespace {

// embreeMemoryEstimate's rates: peaks reported by the memory monitor on 2 cores were 73 bytes a
// triangle (vertices included) for 125 unique meshes of 10.5 M triangles, 9.3 MB for one mesh of 69 k
// triangles, 21 MB for 4 meshes under 10,000 instances (docs/performance.md); these rates lie above
// every one of them.
constexpr std::uint64_t kEmbreeBytesPerTriangle = 72;
constexpr std::uint64_t kEmbreeBytesPerVertex = 16;  // its padded copy of the positions
constexpr std::uint64_t kEmbreeBytesPerInstance = 400;
constexpr std::uint64_t kEmbreeFixedBytes = std::uint64_t(8) << 20;  // device and per-thread blocks

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
  impl.instances =
      makeEmbreeInstances(impl.meshes, scene, hierarchy, impl.materials, instanceNodes, nodesCenter(hierarchy, nodes));
}

EmbreeScene::~EmbreeScene() = default;
EmbreeScene::EmbreeScene(EmbreeScene&&) noexcept = default;
EmbreeScene& EmbreeScene::operator=(EmbreeScene&&) noexcept = default;

void EmbreeScene::render(const Camera& camera, Framebuffer& framebuffer) const {
  castRays(impl_->instances, camera, framebuffer);
}

const glm::dvec3& EmbreeScene::origin() const { return impl_->instances.origin; }

std::uint64_t EmbreeScene::bytes() const {
  return std::uint64_t(std::max<std::int64_t>(0, impl_->meshes.allocations->bytes));
}

std::uint64_t EmbreeScene::peakBytes() const {
  return std::uint64_t(std::max<std::int64_t>(0, impl_->meshes.allocations->peakBytes));
}

std::uint64_t embreeMemoryEstimate(const Scene& scene, const Hierarchy& hierarchy) {
  std::vector<char> used(scene.meshes.size(), 0);
  std::uint64_t instances = 0;
  for (std::uint32_t node : rayInstanceNodes(scene, hierarchy, allNodes(scene))) {
    used[std::size_t(scene.nodes[node].mesh)] = 1;
    ++instances;
  }
  std::uint64_t bytes = 0;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    if (!used[m]) continue;
    const Mesh& mesh = scene.meshes[m];
    bytes += mesh.triangleCount() * kEmbreeBytesPerTriangle + mesh.vertexCount() * kEmbreeBytesPerVertex;
  }
  return kEmbreeFixedBytes + bytes + instances * kEmbreeBytesPerInstance;
}

}  // namespace pbs
