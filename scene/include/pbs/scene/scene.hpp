// The scene model: meshes, materials, textures and a node hierarchy in which a mesh used by several
// nodes is stored once (an instance). Plain data; derived per-node values live in hierarchy.hpp.
#pragma once

#include "pbs/raster/bounds.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace pbs {

enum class TextureWrap : std::uint8_t { Repeat, ClampToEdge, MirroredRepeat };
enum class TextureFilter : std::uint8_t { Nearest, Linear };

// A decoded image with the sampler that reads it.
struct Texture {
  std::string name;
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<std::uint8_t> rgba8;  // width * height * 4 bytes, top row first
  TextureWrap wrapS = TextureWrap::Repeat;
  TextureWrap wrapT = TextureWrap::Repeat;
  TextureFilter magFilter = TextureFilter::Linear;
  TextureFilter minFilter = TextureFilter::Linear;
};

struct Material {
  std::string name;
  glm::vec4 baseColorFactor{1.0f};  // linear RGBA
  std::int32_t baseColorTexture = -1;  // index into Scene::textures, or -1
};

// A run of triangles of one mesh drawn with one material.
struct MeshPart {
  std::uint32_t firstIndex = 0;  // into Mesh::indices, a multiple of 3
  std::uint32_t indexCount = 0;  // a multiple of 3
  std::uint32_t material = 0;    // index into Scene::materials
};

struct Mesh {
  std::string name;
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // one per position, unit length (computed when the file has none)
  std::vector<glm::vec2> uvs;      // empty, or one per position
  std::vector<std::uint32_t> indices;  // three per triangle
  std::vector<MeshPart> parts;         // cover `indices` in order
  Bounds bounds;                       // of `positions`, in the mesh's own frame

  std::uint64_t triangleCount() const { return indices.size() / 3; }
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

// Area-weighted vertex normals from the triangles (degenerate triangles contribute nothing;
// a vertex touched by none gets +Z so no NaN ever leaves this function).
std::vector<glm::vec3> computeVertexNormals(const std::vector<glm::vec3>& positions,
                                            const std::vector<std::uint32_t>& indices);

}  // namespace pbs
