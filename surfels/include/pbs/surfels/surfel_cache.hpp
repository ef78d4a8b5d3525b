// A .surfels file read as frames need it: opened by its tables alone, each array's chunks read the
// first time a frame draws that much of its prefix, and the arrays drawn longest ago dropped when the
// loaded surfels pass a byte budget. Memory follows what is drawn, not the size of the file, and the
// frames are the same bits as with the whole file read (the same surfels, decoded the same way).
#pragma once

#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/scene.hpp"
#include "pbs/surfels/lod_render.hpp"
#include "pbs/surfels/scene_surfels.hpp"
#include "pbs/surfels/surfel_file.hpp"

#include <cstdint>
#include <filesystem>
#include <vector>

namespace pbs {

struct SurfelCacheStats {
  std::uint64_t bytesRead = 0;    // from the file: chunks and their checksums
  std::uint64_t bytesLoaded = 0;  // decoded surfels held now (kSplatBytesPerSurfel each)
  std::uint64_t peakBytesLoaded = 0;
  std::uint64_t arraysDropped = 0;  // to keep within the budget
};

// Requires `reader`'s file to belong to `scene` (its fingerprint; InputError naming the file otherwise),
// then analyses the scene's hierarchy with the instance boxes the file stores (version 4), reading no
// vertex, or from the vertices (analyzeHierarchy) for an older file. Either way the same Hierarchy.
Hierarchy hierarchyWithSurfels(const Scene& scene, SurfelFileReader& reader);

class SurfelCache {
 public:
  // Reads and checks the header and tables, requires the file to belong to `scene` (its fingerprint)
  // and matches its nodes to the scene's; InputErrors name the file. `budgetBytes` bounds the loaded
  // surfels between frames; a frame that needs more than the budget still gets all of it.
  SurfelCache(const std::filesystem::path& file, const Scene& scene, const Hierarchy& hierarchy,
              std::uint64_t budgetBytes);
  // The same from a reader already opened and required for `scene` (SurfelFileReader::requireScene, as
  // hierarchyWithSurfels does); std::logic_error for one that was not.
  SurfelCache(SurfelFileReader reader, const Scene& scene, const Hierarchy& hierarchy, std::uint64_t budgetBytes);

  // Every array with its length and packing values; of the surfels, only what load() brought in.
  const SceneSurfels& surfels() const { return surfels_; }

  // Makes every prefix that `draws` draws loaded, reading whole chunks, and one chunk more of a prefix
  // that grew since the array was last drawn (it is likely to grow again: the camera approaches).
  // Then, while over the budget, drops the arrays drawn longest ago that `draws` does not use. A
  // corrupt chunk throws InputError naming the node.
  void load(const LodDraws& draws);

  // For a caller that decides itself what to read and when (a simulated link, surfel_stream.hpp):
  // reads whole chunks of `array` until at least min(count, its size) surfels are loaded.
  void loadPrefix(std::uint32_t array, std::size_t count);
  // Records `draws` as drawn now, then drops arrays as load() does; reads nothing.
  void keep(const LodDraws& draws);

  const SurfelCacheStats& stats() const { return stats_; }
  const SurfelFileOptions& options() const { return reader_.options(); }        // what the arrays were made with
  std::span<const SurfelArrayInfo> arrays() const { return reader_.arrays(); }  // the file's array table
  std::uint64_t tablesBytes() const { return reader_.tablesBytes(); }           // what opening the file read
  // The file's bytes for `surfels` surfels of `array` from a chunk's start (storedSurfelBytes with the
  // array's colour encoding).
  std::uint64_t storedBytes(std::uint32_t array, std::uint64_t surfels) const {
    return storedSurfelBytes(surfels, reader_.arrays()[array].colorEncoding);
  }

 private:
  // Records the draws as this call's; returns the arrays whose prefix grew since the call before.
  std::vector<std::uint32_t> markDrawn(const LodDraws& draws);
  void dropOverBudget();

  SurfelFileReader reader_;
  SceneSurfels surfels_;
  std::uint64_t budget_;
  std::uint64_t frame_ = 0;               // load() and keep() calls so far
  std::vector<std::uint64_t> lastDrawn_;  // per array: the load() call that last drew it (0: never)
  std::vector<std::size_t> lastCount_;    // per array: the prefix it drew then
  SurfelCacheStats stats_;
};

}  // namespace pbs
