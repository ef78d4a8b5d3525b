// closedOutward and meshFacing: the edge-pairing test and the signed volume of a mesh.
#include "pbs/scene/mesh_closure.hpp"

#include <meshoptimizer.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace pbs {
namespace {

struct Closure {
  bool closed = false;
  double volume = 0.0;  // six times the enclosed signed volume, where closed
};

Closure closureOf(const Mesh& mesh) {
  const std::vector<glm::vec3>& positions = mesh.positions;
  const std::vector<std::uint32_t>& indices = mesh.indices;
  if (indices.size() < 3) return {};
  // Welded vertex ids: one per distinct position, by its bits (meshoptimizer's remap of the positions alone),
  // with +0 and −0 made one.
  std::vector<glm::vec3> welded(positions.size());
  for (std::size_t v = 0; v < positions.size(); ++v) {
    const glm::vec3& p = positions[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return {};
    welded[v] = p + 0.0f;
  }
  std::vector<unsigned int> weld(positions.size());
  if (!positions.empty())
    meshopt_generateVertexRemap(weld.data(), nullptr, welded.size(), welded.data(), welded.size(), sizeof(glm::vec3));
  std::vector<std::uint64_t> edges;  // directed, from << 32 | to
  edges.reserve(indices.size());
  // Six times the signed volume, about a vertex of the mesh: a closed mesh's volume does not depend on
  // the point, and one near it keeps a mesh far from the origin from cancelling its digits away.
  const glm::dvec3 origin = indices[0] < positions.size() ? glm::dvec3(positions[indices[0]]) : glm::dvec3(0.0);
  double volume = 0.0;
  for (std::size_t t = 0; t + 3 <= indices.size(); t += 3) {
    const std::uint32_t i0 = indices[t], i1 = indices[t + 1], i2 = indices[t + 2];
    if (i0 >= positions.size() || i1 >= positions.size() || i2 >= positions.size()) return {};
    const std::uint32_t a = weld[i0], b = weld[i1], c = weld[i2];
    if (a == b || b == c || c == a) continue;
    edges.push_back(std::uint64_t(a) << 32 | b);
    edges.push_back(std::uint64_t(b) << 32 | c);
    edges.push_back(std::uint64_t(c) << 32 | a);
    const glm::dvec3 p0 = glm::dvec3(positions[i0]) - origin, p1 = glm::dvec3(positions[i1]) - origin,
                     p2 = glm::dvec3(positions[i2]) - origin;
    volume += glm::dot(p0, glm::cross(p1, p2));
  }
  if (edges.empty()) return {};
  std::sort(edges.begin(), edges.end());
  if (std::adjacent_find(edges.begin(), edges.end()) != edges.end()) return {};  // an edge run twice one way
  for (const std::uint64_t edge : edges) {
    const std::uint64_t reversed = edge << 32 | edge >> 32;
    if (!std::binary_search(edges.begin(), edges.end(), reversed)) return {};
  }
  return {true, volume};
}

}  // namespace

bool closedOutward(const Mesh& mesh) {
  const Closure closure = closureOf(mesh);
  return closure.closed && closure.volume > 0.0;
}

MeshFacing meshFacing(const Mesh& mesh) {
  const Closure closure = closureOf(mesh);
  if (!closure.closed) return MeshFacing::open;
  if (closure.volume > 0.0) return MeshFacing::closedOutward;
  return closure.volume < 0.0 ? MeshFacing::closedInward : MeshFacing::open;
}

std::vector<MeshFacing> meshFacings(const Scene& scene) {
  std::vector<MeshFacing> facings(scene.meshes.size(), MeshFacing::open);
  tbb::parallel_for(std::size_t(0), scene.meshes.size(),
                    [&](std::size_t m) { facings[m] = meshFacing(scene.meshes[m]); });
  return facings;
}

}  // namespace pbs
