// Gives flat scenes a hierarchy: a loose octree whose leaves hold at most N triangles.
#pragma once

#include "pbs/scene/scene.hpp"

#include <cstdint>

namespace pbs {

// Returns a scene with the same geometry (in world space) organised as a loose octree over the
// mesh instances of `scene`: meshes with more than `maxLeafTriangles` triangles are split into
// pieces (once per mesh, so instances still share them), and every leaf holds at most
// `maxLeafTriangles` triangles. Requires a validated scene and maxLeafTriangles ≥ 1.
Scene buildLooseOctree(const Scene& scene, std::uint32_t maxLeafTriangles);

}  // namespace pbs
