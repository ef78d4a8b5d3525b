// Splits a mesh into pieces of at most N triangles by the octants of its triangles' centroids.
#include "mesh_split.hpp"

#include "octree_walk.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>
#include <span>
#include <string>
#include <utility>

namespace pbs::detail {
namespace {

constexpr std::uint32_t kUnmapped = ~0u;

// The part holding index `index`: parts cover the indices in order, so a binary search finds it.
std::size_t partContaining(const std::vector<MeshPart>& parts, std::uint32_t index) {
  const auto after = std::upper_bound(parts.begin(), parts.end(), index,
                                      [](std::uint32_t i, const MeshPart& part) { return i < part.firstIndex; });
  return static_cast<std::size_t>(after - parts.begin()) - 1;
}

// The piece made of the source triangles `triangles`, in that order. `remap` (source vertex to
// piece vertex) is all kUnmapped on entry and again on return, so one array serves many pieces.
Mesh buildPiece(const Mesh& mesh, std::span<const std::uint32_t> triangles, std::vector<std::uint32_t>& remap) {
  Mesh piece;
  std::vector<std::uint32_t> sourceVertex;  // of each piece vertex
  sourceVertex.reserve(triangles.size());   // a closed mesh has about half a vertex per triangle
  piece.indices.reserve(triangles.size() * 3);
  std::size_t sourcePart = mesh.parts.size();  // of the previous triangle; none yet
  for (const std::uint32_t triangle : triangles) {
    const std::uint32_t first = triangle * 3;
    if (!mesh.parts.empty()) {
      // Triangles of one source part are consecutive here (source order), so a new piece part
      // starts exactly where the source part changes.
      const std::size_t part = partContaining(mesh.parts, first);
      if (part != sourcePart)
        piece.parts.push_back({static_cast<std::uint32_t>(piece.indices.size()), 0, mesh.parts[part].material});
      piece.parts.back().indexCount += 3;
      sourcePart = part;
    }
    for (std::uint32_t corner = 0; corner < 3; ++corner) {
      const std::uint32_t v = mesh.indices[first + corner];
      if (remap[v] == kUnmapped) {
        remap[v] = static_cast<std::uint32_t>(sourceVertex.size());
        sourceVertex.push_back(v);
      }
      piece.indices.push_back(remap[v]);
    }
  }
  for (const std::uint32_t v : sourceVertex) remap[v] = kUnmapped;

  const auto gather = [&](const auto& source, auto& target) {
    if (source.size() != mesh.positions.size()) return;  // an absent attribute stays absent
    target.reserve(sourceVertex.size());
    for (const std::uint32_t v : sourceVertex) target.push_back(source[v]);
  };
  gather(mesh.positions, piece.positions);
  gather(mesh.normals, piece.normals);
  gather(mesh.uvs, piece.uvs);
  updateMeshBounds(piece);
  return piece;
}

}  // namespace

std::vector<Mesh> splitMesh(const Mesh& mesh, std::uint32_t maxTriangles) {
  if (mesh.triangleCount() <= maxTriangles) return {mesh};

  const auto triangleCount = static_cast<std::uint32_t>(mesh.triangleCount());
  std::vector<glm::vec3> centroids(triangleCount);
  tbb::parallel_for(std::uint32_t(0), triangleCount, [&](std::uint32_t t) {
    const std::uint32_t* corner = &mesh.indices[std::size_t(t) * 3];
    centroids[t] = (mesh.positions[corner[0]] + mesh.positions[corner[1]] + mesh.positions[corner[2]]) / 3.0f;
  });

  // The leaves' ranges of `triangles`, in walk order: that order numbers the pieces.
  std::vector<std::uint32_t> triangles(triangleCount);
  std::iota(triangles.begin(), triangles.end(), 0u);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> leaves;
  walkOctree<glm::vec3>(
      triangles, centroids, [&](std::span<const std::uint32_t> cell) { return cell.size() <= maxTriangles; },
      [&](const OctreeCell& cell) {
        if (cell.leaf) leaves.emplace_back(cell.begin, cell.end);
      });

  std::vector<Mesh> pieces(leaves.size());
  tbb::enumerable_thread_specific<std::vector<std::uint32_t>> remaps(mesh.positions.size(), kUnmapped);
  tbb::parallel_for(std::size_t(0), leaves.size(), [&](std::size_t k) {
    const auto [begin, end] = leaves[k];
    pieces[k] = buildPiece(mesh, std::span<const std::uint32_t>(triangles).subspan(begin, end - begin), remaps.local());
    pieces[k].name = mesh.name + " piece " + std::to_string(k);
  });
  return pieces;
}

}  // namespace pbs::detail
