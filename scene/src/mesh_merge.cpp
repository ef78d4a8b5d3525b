// Merging transformed meshes into one, with parts regrouped by material.
#include "mesh_merge.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace pbs {
namespace {

// The cofactor matrix, det · inverse transpose: it carries normals correctly even for a
// singular transform, where the inverse does not exist.
glm::dmat3 cofactor(const glm::dmat3& m) {
  return glm::dmat3(glm::cross(m[1], m[2]), glm::cross(m[2], m[0]), glm::cross(m[0], m[1]));
}

struct PartRef {
  std::uint32_t material;
  std::uint32_t piece;
  std::uint32_t part;
};

}  // namespace

Mesh mergeMeshes(std::span<const MeshPiece> pieces, std::string name) {
  Mesh merged;
  merged.name = std::move(name);
  std::size_t vertexCount = 0, indexCount = 0;
  bool anyUvs = false;
  for (const MeshPiece& piece : pieces) {
    vertexCount += piece.mesh->positions.size();
    indexCount += piece.mesh->indices.size();
    anyUvs = anyUvs || !piece.mesh->uvs.empty();
  }
  if (vertexCount > std::numeric_limits<std::uint32_t>::max() || indexCount > std::numeric_limits<std::uint32_t>::max())
    throw std::length_error("mergeMeshes: '" + merged.name + "' needs more than 32-bit indices");
  merged.positions.reserve(vertexCount);
  merged.normals.reserve(vertexCount);
  if (anyUvs) merged.uvs.reserve(vertexCount);
  merged.indices.reserve(indexCount);

  std::vector<std::uint32_t> firstVertex(pieces.size());
  std::vector<PartRef> parts;
  for (std::size_t p = 0; p < pieces.size(); ++p) {
    const Mesh& mesh = *pieces[p].mesh;
    const glm::dmat4& m = pieces[p].transform;
    const glm::dmat3 linear(m);
    const glm::dmat3 normalMatrix = cofactor(linear) * (glm::determinant(linear) < 0.0 ? -1.0 : 1.0);
    firstVertex[p] = std::uint32_t(merged.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      merged.positions.push_back(glm::vec3(m * glm::dvec4(glm::dvec3(mesh.positions[v]), 1.0)));
      const glm::dvec3 n = normalMatrix * glm::dvec3(mesh.normals[v]);
      const double length = glm::length(n);
      merged.normals.push_back(length > 0.0 && std::isfinite(length) ? glm::vec3(n / length) : glm::vec3(0, 0, 1));
    }
    if (anyUvs) {
      if (mesh.uvs.empty())
        merged.uvs.resize(merged.positions.size(), glm::vec2(0.0f));
      else
        merged.uvs.insert(merged.uvs.end(), mesh.uvs.begin(), mesh.uvs.end());
    }
    for (std::size_t k = 0; k < mesh.parts.size(); ++k)
      if (mesh.parts[k].indexCount > 0)
        parts.push_back({mesh.parts[k].material + pieces[p].materialOffset, std::uint32_t(p), std::uint32_t(k)});
  }

  // Stable, so within a material the triangles keep the pieces' order.
  std::stable_sort(parts.begin(), parts.end(),
                   [](const PartRef& a, const PartRef& b) { return a.material < b.material; });
  for (const PartRef& ref : parts) {
    const MeshPiece& piece = pieces[ref.piece];
    const MeshPart& part = piece.mesh->parts[ref.part];
    const bool mirrored = glm::determinant(glm::dmat3(piece.transform)) < 0.0;
    if (merged.parts.empty() || merged.parts.back().material != ref.material)
      merged.parts.push_back({std::uint32_t(merged.indices.size()), 0, ref.material});
    const std::uint32_t base = firstVertex[ref.piece];
    for (std::uint32_t i = part.firstIndex; i < part.firstIndex + part.indexCount; i += 3) {
      const std::uint32_t* t = &piece.mesh->indices[i];
      if (mirrored)
        merged.indices.insert(merged.indices.end(), {base + t[0], base + t[2], base + t[1]});
      else
        merged.indices.insert(merged.indices.end(), {base + t[0], base + t[1], base + t[2]});
    }
    merged.parts.back().indexCount = std::uint32_t(merged.indices.size()) - merged.parts.back().firstIndex;
  }
  updateMeshBounds(merged);
  return merged;
}

}  // namespace pbs
