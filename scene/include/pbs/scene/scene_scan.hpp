// One pass over a scene's meshes for everything that needs their vertices but not all of them at once:
// the scene and mesh fingerprints, the exact box of every instance (in the world, and in the frames of
// chosen subtrees), and the subtree areas. Meshes are read in index order, a few at a time, and dropped
// as soon as their part is done, so a scene opened without its mesh arrays (lazy_meshes.hpp) is scanned
// in the memory of a few meshes; every value is bit for bit what the whole-scene functions give.
#pragma once

#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/mesh_closure.hpp"
#include "pbs/scene/scene.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace pbs {

struct SceneScanRequest {
  bool worldBounds = false;                      // fill SceneScan::instanceBounds
  std::span<const std::uint32_t> subtreeStarts;  // fill SceneScan::subtreeBounds for these nodes
  bool ownFrameAreas = false;                    // fill SceneScan::ownFrameAreas
  bool meshClosures = false;                     // fill SceneScan::meshClosures
};

struct SceneScan {
  std::uint64_t sceneFingerprint = 0;           // sceneFingerprint(scene), its meshes read
  std::vector<std::uint64_t> meshFingerprints;  // meshFingerprint of each mesh
  std::vector<Bounds> instanceBounds;           // analyzeHierarchy's instanceBounds, one per node
  // Per subtree start, analyzeSubtree's instance boxes in subtreeInstances order (for analyzeSubtree with
  // boxes given).
  std::vector<std::vector<Bounds>> subtreeBounds;
  std::vector<double> ownFrameAreas;      // ownFrameSurfaceAreas, one per node
  std::vector<MeshClosure> meshClosures;  // meshClosure of each mesh
};

// `structure` supplies world transforms and the preorder (analyzeStructure's, or analyzeHierarchy's).
// Reads each mesh once, side by side on the thread pool, holding at most a few per thread. Errors from
// `read` propagate.
SceneScan scanScene(const Scene& scene, const Hierarchy& structure, const SceneScanRequest& request,
                    const MeshReader& read);

}  // namespace pbs
