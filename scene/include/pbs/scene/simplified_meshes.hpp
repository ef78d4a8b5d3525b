// Simplified copies of a scene's meshes (meshoptimizer's edge collapse, meshopt_simplify): the
// triangle budget a user would cut instead of drawing surfels, so `pbs eval` can compare the two.
#pragma once

#include "pbs/scene/scene.hpp"

#include <cstdint>

namespace pbs {

struct SimplifyOptions {
  double ratio = 0.25;  // fraction of each part's triangles to keep, in (0, 1]; 1 keeps the mesh as it is
  // The largest deformation a collapse may cause, relative to the mesh's extent: simplification stops
  // there even above the ratio's triangle count.
  double targetError = 1e-2;
};

struct SimplifiedMesh {
  Mesh mesh;
  float error = 0.0f;  // the deformation reached, relative to the mesh's extent
};

// Simplifies every part on its own (materials never bleed into each other), then keeps only the
// vertices the new triangles use, positions, normals and uvs alike, so drawing transforms no more
// vertices than it needs. A mesh of several parts keeps its border vertices in place, so no crack
// opens where parts meet (open borders of the mesh stay too). Meshes without
// triangles, with non-finite positions, indices out of range, attribute arrays of another length or
// parts that do not cover the indices come back unchanged (nothing to simplify, or nothing
// meshoptimizer may safely read). Throws std::invalid_argument for a ratio outside (0, 1].
SimplifiedMesh simplifyMesh(const Mesh& mesh, const SimplifyOptions& options);

struct SimplifiedScene {
  Scene scene;                        // the input's nodes, transforms, materials and textures; every mesh simplified
  std::uint64_t trianglesBefore = 0;  // over the meshes, each counted once (not per instance)
  std::uint64_t trianglesAfter = 0;
  float largestError = 0.0f;  // over the meshes
};

// simplifyMesh on every mesh, in parallel; the result does not depend on the thread count. Node
// indices are unchanged, so the input's Hierarchy (transforms, bounds that still hold every vertex)
// serves the copy too.
SimplifiedScene simplifyScene(const Scene& scene, const SimplifyOptions& options);

}  // namespace pbs
