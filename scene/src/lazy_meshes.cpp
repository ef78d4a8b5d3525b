// LazyMeshes: meshes decoded into the scene on first draw, checked, and unloaded least recently used first.
#include "pbs/scene/lazy_meshes.hpp"

#include "pbs/scene/input_error.hpp"
#include "pbs/scene/scene_fingerprint.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <utility>

namespace pbs {

LazyMeshes::LazyMeshes(Scene& scene, Decode decode, std::vector<std::uint64_t> fingerprints, std::string source,
                       std::uint64_t budgetBytes)
    : scene_(scene),
      decode_(std::move(decode)),
      fingerprints_(std::move(fingerprints)),
      source_(std::move(source)),
      budget_(budgetBytes),
      lastUsed_(scene.meshes.size(), 0) {
  if (fingerprints_.size() != scene_.meshes.size())
    throw std::invalid_argument("LazyMeshes: " + std::to_string(fingerprints_.size()) + " fingerprints for " +
                                std::to_string(scene_.meshes.size()) + " meshes");
  for (const Mesh& mesh : scene_.meshes) stats_.loaded += mesh.loaded() ? 1 : 0;
}

void LazyMeshes::require(std::span<const std::uint32_t> meshes) {
  ++call_;
  std::vector<std::uint32_t> missing;
  for (std::uint32_t m : meshes) {
    if (lastUsed_[m] == call_) continue;  // named twice
    lastUsed_[m] = call_;
    if (!scene_.meshes[m].loaded()) missing.push_back(m);
  }
  if (missing.empty()) return;
  const auto start = std::chrono::steady_clock::now();
  std::vector<Mesh> decoded(missing.size());
  tbb::parallel_for(std::size_t(0), missing.size(), [&](std::size_t i) { decoded[i] = decode_(missing[i]); });
  for (std::size_t i = 0; i < missing.size(); ++i) {
    const std::uint32_t m = missing[i];
    if (meshFingerprint(decoded[i]) != fingerprints_[m]) {
      char text[160];
      std::snprintf(text, sizeof text,
                    "differs from the mesh the surfels were made from (fingerprint %016llx, expected %016llx): "
                    "run pbs surfelize again",
                    static_cast<unsigned long long>(meshFingerprint(decoded[i])),
                    static_cast<unsigned long long>(fingerprints_[m]));
      throw InputError(source_, "mesh " + std::to_string(m), text);
    }
    stats_.bytesLoaded += meshBytes(decoded[i]);
    scene_.meshes[m] = std::move(decoded[i]);
  }
  stats_.decoded += missing.size();
  stats_.loaded += missing.size();
  stats_.peakBytesLoaded = std::max(stats_.peakBytesLoaded, stats_.bytesLoaded);
  stats_.decodeSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::vector<std::uint32_t> LazyMeshes::unloadOverBudget() {
  std::vector<std::uint32_t> unloaded;
  if (stats_.bytesLoaded <= budget_) return unloaded;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> candidates;  // (last used, mesh), oldest first
  for (std::uint32_t m = 0; m < scene_.meshes.size(); ++m)
    if (lastUsed_[m] != call_ && !scene_.meshes[m].parts.empty() && scene_.meshes[m].loaded())
      candidates.emplace_back(lastUsed_[m], m);
  std::sort(candidates.begin(), candidates.end());
  for (const auto& [used, m] : candidates) {
    if (stats_.bytesLoaded <= budget_) break;
    Mesh& mesh = scene_.meshes[m];
    stats_.bytesLoaded -= meshBytes(mesh);
    Mesh shell;
    shell.name = std::move(mesh.name);
    shell.parts = std::move(mesh.parts);
    mesh = std::move(shell);
    unloaded.push_back(m);
  }
  stats_.unloaded += unloaded.size();
  stats_.loaded -= unloaded.size();
  return unloaded;
}

}  // namespace pbs
