// sceneFingerprint: Hash64 over everything in a scene that shapes its surfels, names excluded.
#include "pbs/scene/scene_fingerprint.hpp"

#include "pbs/raster/hash64.hpp"

#include <bit>
#include <stdexcept>
#include <string>

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

// A list of 32-bit values (floats by their bits) with its length first: each value's little-endian bytes,
// which on a little-endian machine are the array's own bytes, fed at once (a mesh's arrays are most of
// what a scene's fingerprint hashes).
template <class Vector>
void hashWords(Hash64& h, const std::vector<Vector>& items) {
  static_assert(sizeof(Vector) % 4 == 0);
  h.u64(items.size());
  if constexpr (std::endian::native == std::endian::little) {
    h.bytes(items.data(), items.size() * sizeof(Vector));
  } else {
    const auto* words = reinterpret_cast<const std::uint32_t*>(items.data());
    for (std::size_t i = 0; i < items.size() * sizeof(Vector) / 4; ++i) h.u32(words[i]);
  }
}

void hashMesh(Hash64& h, const Mesh& mesh) {
  static_assert(sizeof(glm::vec3) == 12 && sizeof(glm::vec2) == 8, "packed vectors");
  hashWords(h, mesh.positions);
  hashWords(h, mesh.normals);
  hashWords(h, mesh.uvs);
  hashWords(h, mesh.indices);
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
    // minFilter's mip-map part (Texture::mipmap) is not hashed: pbs read minFilter as its filter alone
    // until mip levels came (2026-11-29), and hashing it would refuse every .surfels file made of a
    // textured scene before; their captures differ from today's as after any change to the renderer.
    h.u8(static_cast<std::uint8_t>(texture.minFilter));
    h.u64(texture.rgba8.size());
    h.bytes(texture.rgba8.data(), texture.rgba8.size());
  });
}

// The seeds are version tags: change one when what its fingerprint hashes changes.
constexpr std::uint64_t kSceneSeed = 0x5042'5343'454E'4531ull;
constexpr std::uint64_t kStructureSeed = 0x5042'5353'5452'5543ull;

}  // namespace

// Both fingerprints hash the node graph, then each mesh (whole, or its parts alone), then the materials
// and textures.
SceneFingerprinter::SceneFingerprinter(const Scene& scene) : scene_(scene), hash_(kSceneSeed) {
  hashNodes(hash_, scene);
  hash_.u64(scene.meshes.size());
}

void SceneFingerprinter::add(const Mesh& mesh) {
  ++added_;
  hashMesh(hash_, mesh);
}

std::uint64_t SceneFingerprinter::finish() {
  if (added_ != scene_.meshes.size())
    throw std::logic_error("SceneFingerprinter: " + std::to_string(added_) + " meshes added of " +
                           std::to_string(scene_.meshes.size()));
  hashLooks(hash_, scene_);
  return hash_.digest();
}

std::uint64_t sceneFingerprint(const Scene& scene) {
  SceneFingerprinter fingerprint(scene);
  for (const Mesh& mesh : scene.meshes) fingerprint.add(mesh);
  return fingerprint.finish();
}

std::uint64_t structureFingerprint(const Scene& scene) {
  Hash64 h(kStructureSeed);
  hashNodes(h, scene);
  hashList(h, scene.meshes, [&](const Mesh& mesh) { hashParts(h, mesh); });
  hashLooks(h, scene);
  return h.digest();
}

std::uint64_t meshFingerprint(const Mesh& mesh) {
  Hash64 h(0x5042'534D'4553'4831ull);
  hashMesh(h, mesh);
  return h.digest();
}

}  // namespace pbs
