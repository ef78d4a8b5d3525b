// A scene whose mesh arrays are read when they are first needed. The scene is opened with its node
// graph, transforms, materials, textures and each mesh's parts, but no vertex (Mesh::loaded() false);
// LazyMeshes decodes a mesh's arrays into it on demand, checks them against the fingerprint recorded when
// the surfels were made (or when the scene was first scanned), and unloads the least recently used again
// when the loaded meshes pass a byte budget. Memory follows the geometry being drawn or captured, not the
// size of the scene.
#pragma once

#include "pbs/scene/scene.hpp"

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <span>
#include <string>
#include <vector>

namespace pbs {

struct LazyMeshStats {
  std::uint64_t decoded = 0;      // meshes decoded so far (one decoded again after unloading counts again)
  std::uint64_t unloaded = 0;     // to keep within the budget
  std::uint64_t loaded = 0;       // meshes loaded now
  std::uint64_t bytesLoaded = 0;  // meshBytes of those
  std::uint64_t peakBytesLoaded = 0;
  double decodeSeconds = 0.0;  // summed over the require() calls that decoded
};

class LazyMeshes {
 public:
  // The arrays of mesh `mesh` as the eager importer gives them; it may be called from several threads
  // at once, for different meshes.
  using Decode = std::function<Mesh(std::uint32_t mesh)>;

  // Keeps the meshes it names loaded until it is destroyed (or moved from): what a frame draws or a
  // capture renders cannot be unloaded under it. Must not outlive its LazyMeshes.
  class Lease {
   public:
    Lease() = default;
    Lease(Lease&& other) noexcept;
    Lease& operator=(Lease&& other) noexcept;
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    ~Lease();

   private:
    friend class LazyMeshes;
    Lease(LazyMeshes* owner, std::vector<std::uint32_t> meshes) : owner_(owner), meshes_(std::move(meshes)) {}
    void release();
    LazyMeshes* owner_ = nullptr;
    std::vector<std::uint32_t> meshes_;  // distinct
  };

  // `scene` must outlive this object; its meshes are decoded into it in place. `fingerprints` holds
  // meshFingerprint of every mesh as it was when its surfels were made; a decoded mesh that differs is an
  // InputError naming `source` and the mesh. `budgetBytes` bounds the loaded meshes that no lease holds
  // (leased meshes stay, whatever their size). Throws std::invalid_argument for a fingerprint count other
  // than the scene's meshes.
  LazyMeshes(Scene& scene, Decode decode, std::vector<std::uint64_t> fingerprints, std::string source,
             std::uint64_t budgetBytes);

  // Loads every mesh of `meshes` not loaded yet (side by side), marks them all as used now and leases
  // them. Safe to call from several threads at once: a mesh another call is decoding is waited for, not
  // decoded twice. While the lease lives, scene.meshes[m] of a leased m may be read from any thread.
  [[nodiscard]] Lease require(std::span<const std::uint32_t> meshes);
  // require() of the meshes the scene nodes `nodes` draw (a node without a mesh draws none).
  [[nodiscard]] Lease requireDrawnBy(std::span<const std::uint32_t> nodes);
  // Unloads the meshes used longest ago that no lease holds until the loaded bytes are within the budget;
  // returns them, so that what holds their arrays (a ray caster's BVH) lets go too.
  std::vector<std::uint32_t> unloadOverBudget();

  LazyMeshStats stats() const;
  std::uint64_t budgetBytes() const { return budget_; }

 private:
  enum class State : std::uint8_t { Unloaded, Loading, Loaded };
  // Decodes and checks `meshes` (claimed as Loading by this thread) and installs them.
  void load(std::span<const std::uint32_t> meshes);
  void release(std::span<const std::uint32_t> meshes);

  Scene& scene_;
  Decode decode_;
  std::vector<std::uint64_t> fingerprints_;
  std::string source_;
  std::uint64_t budget_;
  // Under mutex_: everything below.
  mutable std::mutex mutex_;
  std::condition_variable loadedOrFailed_;
  std::uint64_t tick_ = 0;               // require() calls so far
  std::vector<std::uint64_t> lastUsed_;  // per mesh: the require() call that last named it (0: never)
  std::vector<std::uint32_t> leases_;    // per mesh: leases holding it
  std::vector<State> state_;
  LazyMeshStats stats_;
};

}  // namespace pbs
