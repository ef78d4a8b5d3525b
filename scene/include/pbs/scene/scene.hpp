// The scene model: meshes, materials, textures and a node hierarchy in which a mesh used by several
// nodes is stored once (an instance). Plain data; derived per-node values live in hierarchy.hpp.
#pragma once

#include "pbs/raster/bounds.hpp"
#include "pbs/raster/mesh_part.hpp"
#include "pbs/raster/texture.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace pbs {

struct Material {
  std::string name;
  glm::vec4 baseColorFactor{1.0f};     // linear RGBA
  std::int32_t baseColorTexture = -1;  // index into Scene::textures, or -1
};

struct Mesh {
  std::string name;
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;      // one per position, unit length (computed when the file has none)
  std::vector<glm::vec2> uvs;          // empty, or one per position
  std::vector<std::uint32_t> indices;  // three per triangle
  std::vector<MeshPart> parts;         // cover `indices` in order; materials index Scene::materials
  Bounds bounds;                       // of `positions`, in the mesh's own frame

  // From the parts, so that it is known for a mesh whose arrays are not loaded.
  std::uint64_t triangleCount() const {
    std::uint64_t indexCount = 0;
    for (const MeshPart& part : parts) indexCount += part.indexCount;
    return indexCount / 3;
  }
  // False for a mesh of a scene opened without its arrays (LazyMeshes) until they are read: then it has
  // its name, parts and describedVertices, and no positions, normals, uvs, indices or bounds.
  bool loaded() const { return parts.empty() || !indices.empty(); }
  // Of a mesh not loaded: how many vertices it has once read (what a reader foresees memory from).
  std::uint64_t describedVertices = 0;
  std::uint64_t vertexCount() const { return loaded() ? positions.size() : describedVertices; }
};

struct Node {
  std::string name;
  glm::dmat4 local{1.0};  // parent-from-node transform
  std::vector<std::uint32_t> children;
  std::int32_t mesh = -1;  // index into Scene::meshes, or -1
};

// Nodes form a forest: every node has at most one parent and is reachable from exactly one root.
struct Scene {
  std::vector<Node> nodes;
  std::vector<std::uint32_t> roots;
  std::vector<Mesh> meshes;
  std::vector<Material> materials;
  std::vector<Texture> textures;
};

// Recomputes Mesh::bounds from the positions.
void updateMeshBounds(Mesh& mesh);

// Clears the uvs of every mesh no part of which has a textured material: nothing would read them.
// Importers and generators call it last, so a scene holds texture coordinates only where they are used.
void dropUnreadUvs(Scene& scene);
// The same for one mesh, with the scene's materials.
void dropUnreadUvs(const Scene& scene, Mesh& mesh);

// Mesh `mesh`'s arrays for one who reads a scene's meshes one at a time (a scan, a writer): a view of a
// loaded mesh, or one made for the reader and freed with the pointer. Called from several threads at
// once, for different meshes.
using MeshReader = std::function<std::shared_ptr<const Mesh>(std::uint32_t mesh)>;

// A reader of the scene's own meshes (all loaded), copying nothing.
MeshReader loadedMeshes(const Scene& scene);

// The bytes of a mesh's arrays: 12 per position and normal, 8 per texture coordinate pair, 4 per index.
std::uint64_t meshBytes(const Mesh& mesh);
// The same for a mesh not loaded, foreseen from its parts and vertex count (texture coordinates counted
// for every vertex); meshBytes for one that is.
std::uint64_t foreseenMeshBytes(const Mesh& mesh);

// Area-weighted vertex normals from the triangles (degenerate triangles contribute nothing;
// a vertex touched by none gets +Z so no NaN ever leaves this function).
std::vector<glm::vec3> computeVertexNormals(const std::vector<glm::vec3>& positions,
                                            const std::vector<std::uint32_t>& indices);

}  // namespace pbs
