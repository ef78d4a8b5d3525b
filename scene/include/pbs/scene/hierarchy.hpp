// Validation of a scene's references, and the per-node values derived from its hierarchy:
// world transforms, exact world bounds and subtree complexity (instances counted).
#pragma once

#include "pbs/scene/scene.hpp"

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace pbs {

// Throws InputError naming `source` and the element when the scene is not well formed: a
// reference out of range, a node with two parents or in a cycle, a root that is not a root,
// non-finite transforms or vertex data, world transforms whose product overflows (finite local ones
// can), a mesh whose world coordinates pass float's range, index out of range, parts that do not
// cover the indices.
void validateScene(const Scene& scene, std::string_view source);

struct Hierarchy {
  std::vector<std::int32_t> parent;             // -1 for roots
  std::vector<std::uint32_t> depth;             // 0 for roots
  std::vector<glm::dmat4> world;                // world-from-node
  std::vector<Bounds> worldBounds;              // tight box of every world-space vertex in the subtree
  std::vector<Bounds> instanceBounds;           // tight world box of the node's own mesh; empty without one
  std::vector<std::uint64_t> subtreeTriangles;  // counting every instance
  std::vector<std::uint32_t> subtreeMeshNodes;  // nodes with a mesh in the subtree, the node's own included
  std::vector<std::uint32_t> preorder;          // every reachable node, parents before children
};

// Requires a scene that passed validateScene. Runs in parallel over the nodes that carry meshes.
Hierarchy analyzeHierarchy(const Scene& scene);

// The same with every instance's box given (one per node, empty for nodes without a mesh, as a
// .surfels file of this scene stores them): reads no vertex, so it needs only the scene's structure,
// and it is the same Hierarchy, bit for bit, when the boxes are analyzeHierarchy's. Throws
// std::invalid_argument when the count differs from the scene's nodes or a node without a mesh has a
// box that is not empty.
Hierarchy analyzeHierarchy(const Scene& scene, std::span<const Bounds> instanceBounds);

// The same with every box empty: parents, depths, world transforms, preorder and triangle counts, for a
// scene whose vertices are still to be read (a scan that computes the boxes needs the transforms first).
Hierarchy analyzeStructure(const Scene& scene);

// The same for `node`'s subtree alone, seen from the node's own frame: world[node] is the identity
// (its own transform left out), world[n] below it chains the local transforms, worldBounds are tight
// boxes in that frame, preorder lists the subtree and parent[node] is -1. Entries of nodes outside the
// subtree keep their defaults. This is the frame a node's surfels are made and stored in, so every
// instance of the same subtree shares them.
Hierarchy analyzeSubtree(const Scene& scene, std::uint32_t node);

// A node with a mesh in a subtree, with analyzeSubtree's world transform of it (the same product of the
// same local transforms, so the same bits).
struct SubtreeInstance {
  std::uint32_t node;
  glm::dmat4 frameFromInstance;
};
// Those of `node`'s subtree in analyzeSubtree's preorder; touches only the subtree (no per-scene arrays).
std::vector<SubtreeInstance> subtreeInstances(const Scene& scene, std::uint32_t node);

// analyzeSubtree with the instance boxes given, one per subtreeInstances(scene, node) entry in its order:
// reads no vertex, and is analyzeSubtree bit for bit when the boxes are the tight boxes of those
// instances' vertices through their transforms. Throws std::invalid_argument for another count.
Hierarchy analyzeSubtree(const Scene& scene, std::uint32_t node, std::span<const Bounds> instanceBounds);

struct SceneSummary {
  std::uint64_t nodes = 0;
  std::uint64_t meshes = 0;
  std::uint64_t instances = 0;  // nodes that carry a mesh
  std::uint64_t triangles = 0;  // counting instances
  std::uint64_t uniqueTriangles = 0;
  std::uint32_t maxDepth = 0;
  std::uint64_t materials = 0;
  std::uint64_t textures = 0;
  Bounds bounds;
};

SceneSummary summarizeScene(const Scene& scene, const Hierarchy& hierarchy);

}  // namespace pbs
