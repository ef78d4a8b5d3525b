// SurfelCache: prefixes read chunk by chunk as frames draw them, the least recently drawn dropped.
#include "pbs/surfels/surfel_cache.hpp"

#include "pbs/scene/scene_fingerprint.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace pbs {

Hierarchy hierarchyWithSurfels(const Scene& scene, SurfelFileReader& reader) {
  reader.requireScene(sceneFingerprint(scene));
  // The fingerprint ties the boxes to this scene: a file of the same scene holds one per node.
  const std::span<const Bounds> boxes = reader.sceneTable().instanceBounds;
  if (boxes.size() == scene.nodes.size()) return analyzeHierarchy(scene, boxes);
  return analyzeHierarchy(scene);
}

SurfelCache::SurfelCache(const std::filesystem::path& file, const Scene& scene, const Hierarchy& hierarchy,
                         std::uint64_t budgetBytes)
    : SurfelCache(
          [&] {
            SurfelFileReader reader(file);
            reader.requireScene(sceneFingerprint(scene));
            return reader;
          }(),
          scene, hierarchy, budgetBytes) {}

SurfelCache::SurfelCache(SurfelFileReader reader, const Scene& scene, const Hierarchy& hierarchy,
                         std::uint64_t budgetBytes)
    : reader_(std::move(reader)), budget_(budgetBytes) {
  if (!reader_.sceneRequired())
    throw std::logic_error("SurfelCache: the reader was not required for the scene (SurfelFileReader::requireScene)");
  surfels_.arrays.reserve(reader_.arrays().size());
  for (const SurfelArrayInfo& info : reader_.arrays()) surfels_.arrays.push_back(splatArrayOf(info));
  surfels_.arrayOfNode = arrayOfNodes(reader_.nodes(), scene, hierarchy, reader_.path().string());
  lastDrawn_.assign(surfels_.arrays.size(), 0);
  lastCount_.assign(surfels_.arrays.size(), 0);
}

std::vector<std::uint32_t> SurfelCache::markDrawn(const LodDraws& draws) {
  ++frame_;
  std::vector<std::uint32_t> grown;
  for (const LodDraws::Surfels& draw : draws.surfels) {
    const std::uint32_t a = draw.array;
    if (lastDrawn_[a] != frame_) {
      if (lastDrawn_[a] + 1 == frame_ && draw.count > lastCount_[a]) grown.push_back(a);
      lastDrawn_[a] = frame_;
      lastCount_[a] = 0;
    }
    lastCount_[a] = std::max<std::size_t>(lastCount_[a], draw.count);
  }
  return grown;
}

void SurfelCache::load(const LodDraws& draws) {
  const std::vector<std::uint32_t> grown = markDrawn(draws);
  for (const LodDraws::Surfels& draw : draws.surfels) loadPrefix(draw.array, draw.count);
  for (std::uint32_t a : grown) loadPrefix(a, lastCount_[a] + kSurfelsPerChunk);
  dropOverBudget();
}

void SurfelCache::keep(const LodDraws& draws) {
  markDrawn(draws);
  dropOverBudget();
}

void SurfelCache::loadPrefix(std::uint32_t array, std::size_t count) {
  SplatArray& splats = surfels_.arrays[array];
  // Whole chunks: the file checks a chunk at a time, and the next read starts where this one ends.
  const std::size_t chunks = (count + kSurfelsPerChunk - 1) / kSurfelsPerChunk;
  const std::size_t wanted = std::min(splats.size(), chunks * kSurfelsPerChunk);
  if (wanted <= splats.loaded()) return;
  const std::size_t from = splats.loaded();
  const std::vector<Surfel> read = reader_.readRange(array, std::uint32_t(from), std::uint32_t(wanted - from));
  appendSurfels(splats, read);
  stats_.bytesRead = reader_.dataBytesRead();
  stats_.bytesLoaded += read.size() * kSplatBytesPerSurfel;
  stats_.peakBytesLoaded = std::max(stats_.peakBytesLoaded, stats_.bytesLoaded);
}

void SurfelCache::dropOverBudget() {
  if (stats_.bytesLoaded <= budget_) return;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> candidates;  // (last drawn, array), oldest first
  for (std::uint32_t a = 0; a < surfels_.arrays.size(); ++a)
    if (lastDrawn_[a] != frame_ && surfels_.arrays[a].loaded() > 0) candidates.emplace_back(lastDrawn_[a], a);
  std::sort(candidates.begin(), candidates.end());
  for (const auto& [drawn, a] : candidates) {
    if (stats_.bytesLoaded <= budget_) break;
    SplatArray& splats = surfels_.arrays[a];
    stats_.bytesLoaded -= splats.loaded() * kSplatBytesPerSurfel;
    std::vector<glm::vec3>().swap(splats.positions);
    std::vector<glm::vec3>().swap(splats.normals);
    std::vector<glm::u8vec4>().swap(splats.colors);
    ++stats_.arraysDropped;
  }
}

}  // namespace pbs
