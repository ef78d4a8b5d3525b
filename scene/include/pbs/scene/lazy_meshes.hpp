// A scene whose mesh arrays are read when a frame first draws them. The scene is opened with its node
// graph, transforms, materials, textures and each mesh's parts, but no vertex (Mesh::loaded() false);
// LazyMeshes decodes a mesh's arrays into it on demand, checks them against the fingerprint recorded when
// the surfels were made, and unloads the least recently drawn again when the loaded meshes pass a byte
// budget. Memory follows the geometry a frame draws, not the size of the scene.
#pragma once

#include "pbs/scene/scene.hpp"

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace pbs {

struct LazyMeshStats {
  std::uint64_t decoded = 0;    // meshes decoded so far (one decoded again after unloading counts again)
  std::uint64_t unloaded = 0;   // to keep within the budget
  std::uint64_t loaded = 0;     // meshes loaded now
  std::uint64_t bytesLoaded = 0;  // meshBytes of those
  std::uint64_t peakBytesLoaded = 0;
  double decodeSeconds = 0.0;
};

class LazyMeshes {
 public:
  // The arrays of mesh `mesh` as the eager importer gives them; it may be called from several threads
  // at once, for different meshes.
  using Decode = std::function<Mesh(std::uint32_t mesh)>;

  // `scene` must outlive this object; its meshes are decoded into it in place. `fingerprints` holds
  // meshFingerprint of every mesh as it was when its surfels were made; a decoded mesh that differs is an
  // InputError naming `source` and the mesh. `budgetBytes` bounds the loaded meshes between frames (a
  // frame that needs more still gets all of it). Throws std::invalid_argument for a fingerprint count
  // other than the scene's meshes.
  LazyMeshes(Scene& scene, Decode decode, std::vector<std::uint64_t> fingerprints, std::string source,
             std::uint64_t budgetBytes);

  // Loads every mesh of `meshes` not loaded yet (side by side) and marks them all as drawn now.
  void require(std::span<const std::uint32_t> meshes);
  // Unloads the meshes drawn longest ago, never one of the last require(), until the loaded bytes are
  // within the budget; returns them, so that what holds their arrays (a ray caster's BVH) lets go too.
  std::vector<std::uint32_t> unloadOverBudget();

  const LazyMeshStats& stats() const { return stats_; }

 private:
  Scene& scene_;
  Decode decode_;
  std::vector<std::uint64_t> fingerprints_;
  std::string source_;
  std::uint64_t budget_;
  std::uint64_t call_ = 0;               // require() calls so far
  std::vector<std::uint64_t> lastUsed_;  // per mesh: the require() call that last named it (0: never)
  LazyMeshStats stats_;
};

}  // namespace pbs
