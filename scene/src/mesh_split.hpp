// Splits a mesh into pieces of at most N triangles by the octants of its triangles' centroids;
// internal to pbs_scene (the loose octree's first step).
#pragma once

#include "pbs/scene/scene.hpp"

#include <cstdint>
#include <vector>

namespace pbs::detail {

// A mesh of at most `maxTriangles` triangles comes back as its one piece, unchanged. Otherwise the
// pieces, named "NAME piece K", each have compact vertex arrays (positions, normals and uvs of the
// vertices they use), their triangles in source order and parts that keep each triangle's material.
// Together they hold every triangle once. Requires maxTriangles ≥ 1 and a mesh whose parts cover
// its indices in order.
std::vector<Mesh> splitMesh(const Mesh& mesh, std::uint32_t maxTriangles);

}  // namespace pbs::detail
