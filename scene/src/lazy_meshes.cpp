// LazyMeshes: meshes decoded into the scene on first use, checked, leased while in use, and unloaded least
// recently used first.
#include "pbs/scene/lazy_meshes.hpp"

#include "pbs/scene/input_error.hpp"
#include "pbs/scene/scene_fingerprint.hpp"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <utility>

namespace pbs {
namespace {

// Loading and unloading touch a mesh's arrays and bounds only: its name, parts and describedVertices are
// read by any thread at any time (the triangle counts of a subtree being analysed, say), leased or not.
void installArrays(Mesh& mesh, Mesh&& decoded) {
  mesh.positions = std::move(decoded.positions);
  mesh.normals = std::move(decoded.normals);
  mesh.uvs = std::move(decoded.uvs);
  mesh.indices = std::move(decoded.indices);
  mesh.bounds = decoded.bounds;
}

void dropArrays(Mesh& mesh) {
  mesh.positions = {};
  mesh.normals = {};
  mesh.uvs = {};
  mesh.indices = {};
  mesh.bounds = Bounds{};
}

}  // namespace

LazyMeshes::Lease::Lease(Lease&& other) noexcept
    : owner_(std::exchange(other.owner_, nullptr)), meshes_(std::move(other.meshes_)) {}

LazyMeshes::Lease& LazyMeshes::Lease::operator=(Lease&& other) noexcept {
  if (this != &other) {
    release();
    owner_ = std::exchange(other.owner_, nullptr);
    meshes_ = std::move(other.meshes_);
  }
  return *this;
}

LazyMeshes::Lease::~Lease() { release(); }

void LazyMeshes::Lease::release() {
  if (owner_) owner_->release(meshes_);
  owner_ = nullptr;
  meshes_.clear();
}

LazyMeshes::LazyMeshes(Scene& scene, Decode decode, std::vector<std::uint64_t> fingerprints, std::string source,
                       std::uint64_t budgetBytes)
    : scene_(scene),
      decode_(std::move(decode)),
      fingerprints_(std::move(fingerprints)),
      source_(std::move(source)),
      budget_(budgetBytes),
      lastUsed_(scene.meshes.size(), 0),
      leases_(scene.meshes.size(), 0),
      state_(scene.meshes.size(), State::Unloaded) {
  if (fingerprints_.size() != scene_.meshes.size())
    throw std::invalid_argument("LazyMeshes: " + std::to_string(fingerprints_.size()) + " fingerprints for " +
                                std::to_string(scene_.meshes.size()) + " meshes");
  for (std::size_t m = 0; m < scene_.meshes.size(); ++m) {
    if (!scene_.meshes[m].loaded()) continue;
    scene_.meshes[m].describedVertices = scene_.meshes[m].positions.size();
    state_[m] = State::Loaded;
    ++stats_.loaded;
    stats_.bytesLoaded += meshBytes(scene_.meshes[m]);
  }
  stats_.peakBytesLoaded = stats_.bytesLoaded;
}

LazyMeshes::Lease LazyMeshes::requireDrawnBy(std::span<const std::uint32_t> nodes) {
  std::vector<std::uint32_t> meshes;
  for (std::uint32_t node : nodes)
    if (const std::int32_t mesh = scene_.nodes[node].mesh; mesh >= 0) meshes.push_back(std::uint32_t(mesh));
  return require(meshes);
}

LazyMeshes::Lease LazyMeshes::require(std::span<const std::uint32_t> meshes) {
  std::vector<std::uint32_t> distinct(meshes.begin(), meshes.end());
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  for (std::uint32_t m : distinct)
    if (m >= scene_.meshes.size()) throw std::out_of_range("LazyMeshes: mesh " + std::to_string(m) + " out of range");

  std::unique_lock lock(mutex_);
  ++tick_;
  for (std::uint32_t m : distinct) {
    ++leases_[m];
    lastUsed_[m] = tick_;
  }
  lock.unlock();
  Lease lease(this, distinct);  // from here on, a throw gives the leases back
  lock.lock();
  // Decode what no one else is decoding; wait for the rest. A mesh found unloaded again while leased is one
  // whose decoder failed: this call tries it itself (and most likely fails the same way, with the error).
  for (;;) {
    std::vector<std::uint32_t> mine;
    bool waiting = false;
    for (std::uint32_t m : distinct) {
      if (state_[m] == State::Unloaded) {
        state_[m] = State::Loading;
        mine.push_back(m);
      } else if (state_[m] == State::Loading) {
        waiting = true;
      }
    }
    if (!mine.empty()) {
      lock.unlock();
      load(mine);
      lock.lock();
      continue;
    }
    if (!waiting) break;
    loadedOrFailed_.wait(lock);
  }
  return lease;
}

void LazyMeshes::load(std::span<const std::uint32_t> meshes) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<Mesh> decoded(meshes.size());
  try {
    // Isolated: a thread waiting here for its decodes must not take up another task meanwhile (say, a
    // capture that requires a mesh this very call is decoding: it would wait for itself).
    tbb::this_task_arena::isolate([&] {
      tbb::parallel_for(std::size_t(0), meshes.size(), [&](std::size_t i) {
        const std::uint32_t m = meshes[i];
        decoded[i] = decode_(m);
        const std::uint64_t fingerprint = meshFingerprint(decoded[i]);
        if (fingerprint == fingerprints_[m]) return;
        char text[160];
        std::snprintf(text, sizeof text,
                      "differs from the mesh the surfels were made from (fingerprint %016llx, expected %016llx): "
                      "run pbs surfelize again",
                      static_cast<unsigned long long>(fingerprint), static_cast<unsigned long long>(fingerprints_[m]));
        throw InputError(source_, "mesh " + std::to_string(m), text);
      });
    });
  } catch (...) {
    const std::lock_guard lock(mutex_);
    for (std::uint32_t m : meshes) state_[m] = State::Unloaded;
    loadedOrFailed_.notify_all();
    throw;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::lock_guard lock(mutex_);
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const std::uint32_t m = meshes[i];
    stats_.bytesLoaded += meshBytes(decoded[i]);
    installArrays(scene_.meshes[m], std::move(decoded[i]));
    state_[m] = State::Loaded;
  }
  stats_.decoded += meshes.size();
  stats_.loaded += meshes.size();
  stats_.peakBytesLoaded = std::max(stats_.peakBytesLoaded, stats_.bytesLoaded);
  stats_.decodeSeconds += seconds;
  loadedOrFailed_.notify_all();
}

void LazyMeshes::release(std::span<const std::uint32_t> meshes) {
  const std::lock_guard lock(mutex_);
  for (std::uint32_t m : meshes) --leases_[m];
}

std::vector<std::uint32_t> LazyMeshes::unloadOverBudget() {
  const std::lock_guard lock(mutex_);
  std::vector<std::uint32_t> unloaded;
  if (stats_.bytesLoaded <= budget_) return unloaded;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> candidates;  // (last used, mesh), oldest first
  for (std::uint32_t m = 0; m < scene_.meshes.size(); ++m)
    if (state_[m] == State::Loaded && leases_[m] == 0 && !scene_.meshes[m].parts.empty())
      candidates.emplace_back(lastUsed_[m], m);
  std::sort(candidates.begin(), candidates.end());
  for (const auto& [used, m] : candidates) {
    if (stats_.bytesLoaded <= budget_) break;
    Mesh& mesh = scene_.meshes[m];
    stats_.bytesLoaded -= meshBytes(mesh);
    dropArrays(mesh);
    state_[m] = State::Unloaded;
    unloaded.push_back(m);
  }
  stats_.unloaded += unloaded.size();
  stats_.loaded -= unloaded.size();
  return unloaded;
}

LazyMeshStats LazyMeshes::stats() const {
  const std::lock_guard lock(mutex_);
  return stats_;
}

}  // namespace pbs
