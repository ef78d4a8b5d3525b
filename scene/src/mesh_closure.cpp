// meshClosure: the edge-pairing test, the holes capped, and the signed volume of a mesh.
#include "pbs/scene/mesh_closure.hpp"

#include <meshoptimizer.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

namespace pbs {
namespace {

// More holes than this and a mesh counts as open: each triangle of its hidden side would be tested against
// every hole's rectangle, and so many holes leave little of the hidden side out anyway.
constexpr std::size_t kMaxHoles = 64;

struct Closure {
  bool closed = false;  // closed once each hole is capped (holes empty: closed as it is)
  double volume = 0.0;  // six times the enclosed signed volume, caps included, where closed
  std::vector<Bounds> holes;
};

// Each connected part of the boundary (its edges run one way only) capped by a cone from its vertices' mean:
// a cone triangle (apex, b, a) per boundary edge a → b pairs that edge, and the apex's edges pair up where
// each boundary vertex starts as many boundary edges as it ends. Adds the cones' volume; false where a vertex
// does not balance (a boundary that is no set of loops).
bool capHoles(const std::vector<glm::vec3>& positions, const std::vector<unsigned int>& weld,
              const std::vector<std::uint64_t>& boundary, const glm::dvec3& origin, Closure& closure) {
  std::vector<std::uint32_t> vertexOfWeld(positions.size());  // a vertex of each welded id
  for (std::size_t v = positions.size(); v-- > 0;) vertexOfWeld[weld[v]] = std::uint32_t(v);
  std::vector<std::uint32_t> part(vertexOfWeld.size());
  std::iota(part.begin(), part.end(), 0u);
  const auto root = [&](std::uint32_t v) {
    while (part[v] != v) v = part[v] = part[part[v]];
    return v;
  };
  std::vector<std::int64_t> balance(vertexOfWeld.size(), 0);
  for (const std::uint64_t edge : boundary) {
    const auto a = std::uint32_t(edge >> 32), b = std::uint32_t(edge);
    ++balance[a];
    --balance[b];
    part[root(a)] = root(b);
  }
  std::vector<std::int64_t> partOf(vertexOfWeld.size(), -1);  // its hole, for each part's root
  std::vector<glm::dvec3> sum;
  std::vector<std::uint32_t> count;
  for (const std::uint64_t edge : boundary) {
    const auto a = std::uint32_t(edge >> 32);
    if (balance[a] != 0 || balance[std::uint32_t(edge)] != 0) return false;
    const std::uint32_t r = root(a);
    if (partOf[r] < 0) {
      partOf[r] = std::int64_t(closure.holes.size());
      sum.emplace_back(0.0);
      count.push_back(0);
      closure.holes.emplace_back();
    }
  }
  if (closure.holes.size() > kMaxHoles) return false;
  // Each boundary vertex once per edge leaving it: the mean of the vertices with their multiplicity.
  for (const std::uint64_t edge : boundary) {
    const auto a = std::uint32_t(edge >> 32);
    const std::size_t h = std::size_t(partOf[root(a)]);
    const glm::dvec3 p(positions[vertexOfWeld[a]]);
    sum[h] += p;
    ++count[h];
    closure.holes[h].extend(p);
  }
  for (const std::uint64_t edge : boundary) {
    const auto a = std::uint32_t(edge >> 32), b = std::uint32_t(edge);
    const std::size_t h = std::size_t(partOf[root(a)]);
    const glm::dvec3 apex = sum[h] / double(count[h]) - origin;
    const glm::dvec3 pa = glm::dvec3(positions[vertexOfWeld[a]]) - origin,
                     pb = glm::dvec3(positions[vertexOfWeld[b]]) - origin;
    closure.volume += glm::dot(apex, glm::cross(pb, pa));
  }
  return true;
}

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
  Closure closure;
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
    closure.volume += glm::dot(p0, glm::cross(p1, p2));
  }
  if (edges.empty()) return {};
  std::sort(edges.begin(), edges.end());
  if (std::adjacent_find(edges.begin(), edges.end()) != edges.end()) return {};  // an edge run twice one way
  std::vector<std::uint64_t> boundary;
  for (const std::uint64_t edge : edges) {
    const std::uint64_t reversed = edge << 32 | edge >> 32;
    if (!std::binary_search(edges.begin(), edges.end(), reversed)) boundary.push_back(edge);
  }
  if (!boundary.empty() && !capHoles(positions, weld, boundary, origin, closure)) return {};
  closure.closed = true;
  return closure;
}

}  // namespace

MeshClosure meshClosure(const Mesh& mesh) {
  Closure closure = closureOf(mesh);
  if (!closure.closed || closure.volume == 0.0) return {};
  return {closure.volume > 0.0 ? MeshFacing::closedOutward : MeshFacing::closedInward, std::move(closure.holes)};
}

std::vector<MeshClosure> meshClosures(const Scene& scene) {
  std::vector<MeshClosure> closures(scene.meshes.size());
  tbb::parallel_for(std::size_t(0), scene.meshes.size(),
                    [&](std::size_t m) { closures[m] = meshClosure(scene.meshes[m]); });
  return closures;
}

}  // namespace pbs
