// sceneFingerprint: Hash64 over everything in a scene that shapes its surfels, names excluded.
#include "pbs/scene/scene_fingerprint.hpp"

#include "pbs/raster/hash64.hpp"

namespace pbs {
namespace {

// Every list is hashed with its length first, so that moving an element from one list to the next
// (or from one mesh to the next) changes the value.
template <class T, class Each>
void hashList(Hash64& h, const std::vector<T>& items, Each each) {
  h.u64(items.size());
  for (const T& item : items) each(item);
}

void hashParts(Hash64& h, const Mesh& mesh) {
  hashList(h, mesh.parts, [&](const MeshPart& part) {
    h.u32(part.firstIndex);
    h.u32(part.indexCount);
    h.u32(part.material);
  });
}

void hashMesh(Hash64& h, const Mesh& mesh) {
  hashList(h, mesh.positions, [&](const glm::vec3& p) {
    for (int i = 0; i < 3; ++i) h.f32(p[i]);
  });
  hashList(h, mesh.normals, [&](const glm::vec3& n) {
    for (int i = 0; i < 3; ++i) h.f32(n[i]);
  });
  hashList(h, mesh.uvs, [&](const glm::vec2& uv) {
    for (int i = 0; i < 2; ++i) h.f32(uv[i]);
  });
  hashList(h, mesh.indices, [&](std::uint32_t index) { h.u32(index); });
  hashParts(h, mesh);
}

void hashNodes(Hash64& h, const Scene& scene) {
  hashList(h, scene.roots, [&](std::uint32_t root) { h.u32(root); });
  hashList(h, scene.nodes, [&](const Node& node) {
    hashList(h, node.children, [&](std::uint32_t child) { h.u32(child); });
    h.i32(node.mesh);
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) h.f64(node.local[c][r]);
  });
}

void hashLooks(Hash64& h, const Scene& scene) {
  hashList(h, scene.materials, [&](const Material& material) {
    for (int i = 0; i < 4; ++i) h.f32(material.baseColorFactor[i]);
    h.i32(material.baseColorTexture);
  });
  hashList(h, scene.textures, [&](const Texture& texture) {
    h.u32(texture.width);
    h.u32(texture.height);
    // Wrap and filter modes change the sampled colours, so they count too.
    h.u8(static_cast<std::uint8_t>(texture.wrapS));
    h.u8(static_cast<std::uint8_t>(texture.wrapT));
    h.u8(static_cast<std::uint8_t>(texture.magFilter));
    h.u8(static_cast<std::uint8_t>(texture.minFilter));
    h.u64(texture.rgba8.size());
    h.bytes(texture.rgba8.data(), texture.rgba8.size());
  });
}

// The node graph, each mesh as `hashEachMesh` hashes it, and the materials and textures, from `seed`.
template <class HashMesh>
std::uint64_t fingerprintWith(std::uint64_t seed, const Scene& scene, HashMesh hashEachMesh) {
  Hash64 h(seed);
  hashNodes(h, scene);
  hashList(h, scene.meshes, [&](const Mesh& mesh) { hashEachMesh(h, mesh); });
  hashLooks(h, scene);
  return h.digest();
}

}  // namespace

// The seeds are version tags: change one when what its fingerprint hashes changes.
std::uint64_t sceneFingerprint(const Scene& scene) { return fingerprintWith(0x5042'5343'454E'4531ull, scene, hashMesh); }

std::uint64_t structureFingerprint(const Scene& scene) {
  return fingerprintWith(0x5042'5353'5452'5543ull, scene, hashParts);
}

std::uint64_t meshFingerprint(const Mesh& mesh) {
  Hash64 h(0x5042'534D'4553'4831ull);
  hashMesh(h, mesh);
  return h.digest();
}

}  // namespace pbs
