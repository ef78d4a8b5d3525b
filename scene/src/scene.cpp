// Small mesh utilities shared by the importer, the generator and the octree: bounds, normals and unread uvs.
#include "pbs/scene/scene.hpp"

#include <algorithm>
#include <cmath>

namespace pbs {

std::uint64_t meshBytes(const Mesh& mesh) {
  return mesh.positions.size() * sizeof(glm::vec3) + mesh.normals.size() * sizeof(glm::vec3) +
         mesh.uvs.size() * sizeof(glm::vec2) + mesh.indices.size() * sizeof(std::uint32_t);
}

MeshReader loadedMeshes(const Scene& scene) {
  return [&scene](std::uint32_t mesh) {
    // Aliasing an empty owner: a view that frees nothing.
    return std::shared_ptr<const Mesh>(std::shared_ptr<const Mesh>(), &scene.meshes[mesh]);
  };
}

std::uint64_t foreseenMeshBytes(const Mesh& mesh) {
  if (mesh.loaded()) return meshBytes(mesh);
  return 3 * mesh.triangleCount() * sizeof(std::uint32_t) +
         mesh.vertexCount() * (2 * sizeof(glm::vec3) + sizeof(glm::vec2));
}

void dropUnreadUvs(const Scene& scene, Mesh& mesh) {
  const bool textured = std::any_of(mesh.parts.begin(), mesh.parts.end(), [&](const MeshPart& part) {
    return part.material < scene.materials.size() && scene.materials[part.material].baseColorTexture >= 0;
  });
  if (!textured) std::vector<glm::vec2>().swap(mesh.uvs);  // swap: frees the memory, not only the size
}

void dropUnreadUvs(Scene& scene) {
  for (Mesh& mesh : scene.meshes) dropUnreadUvs(scene, mesh);
}

void updateMeshBounds(Mesh& mesh) {
  mesh.bounds = Bounds{};
  for (const glm::vec3& p : mesh.positions) mesh.bounds.extend(glm::dvec3(p));
}

std::vector<glm::vec3> computeVertexNormals(const std::vector<glm::vec3>& positions,
                                            const std::vector<std::uint32_t>& indices) {
  // Accumulate in double: the unnormalised cross product weights each face by twice its area,
  // and huge or tiny scenes would otherwise lose the small faces' contribution.
  std::vector<glm::dvec3> sum(positions.size(), glm::dvec3(0.0));
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    const std::uint32_t a = indices[t], b = indices[t + 1], c = indices[t + 2];
    const glm::dvec3 pa(positions[a]), pb(positions[b]), pc(positions[c]);
    const glm::dvec3 faceNormal = glm::cross(pb - pa, pc - pa);
    sum[a] += faceNormal;
    sum[b] += faceNormal;
    sum[c] += faceNormal;
  }
  std::vector<glm::vec3> normals(positions.size());
  for (std::size_t v = 0; v < positions.size(); ++v) {
    const double length = glm::length(sum[v]);
    normals[v] = (length > 0.0 && std::isfinite(length)) ? glm::vec3(sum[v] / length) : glm::vec3(0.0f, 0.0f, 1.0f);
  }
  return normals;
}

}  // namespace pbs
