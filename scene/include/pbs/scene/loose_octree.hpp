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

// Whether a scene lacks the levels of detail its own hierarchy should give: some node draws a mesh of
// more than `aboveTriangles` triangles (a scan, a CAD export under one node), so that one array would
// stand for all of it. Never for `aboveTriangles` 0. Reads the meshes' parts only, so it works on a scene
// opened without its mesh arrays.
bool needsLooseOctree(const Scene& scene, std::uint64_t aboveTriangles);

// The leaf size of the loose octree surfelize builds for a scene that needs one: the default number of
// subtree triangles above which a node gets an array, so the leaves are drawn as geometry and every
// level above them as surfels.
inline constexpr std::uint32_t kDefaultOctreeLeafTriangles = 10000;
// A node's own mesh above this many triangles makes surfelize build the octree unasked.
inline constexpr std::uint64_t kDefaultOctreeAboveTriangles = 1000000;

}  // namespace pbs
