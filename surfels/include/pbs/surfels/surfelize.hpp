// Surfels for a whole scene (paper, Sec. 2): an ordered surfel array for every node complex enough,
// computed once per distinct subtree and shared by all its instances.
#pragma once

#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/lazy_meshes.hpp"
#include "pbs/scene/scene.hpp"
#include "pbs/surfels/surfel_file.hpp"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pbs {

// What an inner node's capture draws.
enum class CaptureSource : std::uint32_t {
  Triangles = 0,     // its whole subtree's triangles (exact; costs as much as the subtree)
  ChildSurfels = 1,  // its children's surfel arrays as splats, and the triangles of children without one
  // ChildSurfels where that is much cheaper than the triangles (the subtree holds more than
  // kAutoChildSurfelRatio times as many triangles as the children's drawing would hold splats and
  // triangles), Triangles elsewhere: exact where exactness is cheap, fast where it is not.
  Auto = 2,
};
inline constexpr double kAutoChildSurfelRatio = 2.0;

// "triangles", "children", "auto".
std::string_view captureSourceName(CaptureSource source);

struct SurfelizeProgress {
  std::uint32_t arraysDone = 0;
  std::uint32_t arraysTotal = 0;
  std::uint64_t surfels = 0;         // in the arrays done so far
  std::uint64_t trianglesDone = 0;   // subtree triangles of the arrays done: the work measure
  std::uint64_t trianglesTotal = 0;  // (what captures cost, so time-left estimates follow it)
};

// One of `count` machines sharing a surfelize run: shard `index` (0 ≤ index < count).
struct SurfelizeShard {
  std::uint32_t index = 0;
  std::uint32_t count = 1;
};

struct SurfelizeOptions {
  SurfelFileOptions file;  // threshold, max surfels, resolution, directions, ordering, colours, seed
  CaptureSource source = CaptureSource::Auto;
  // surfelizeToFile only: write this shard's part (SurfelShardTable) instead of the whole file. Which
  // arrays each shard holds is a pure function of the scene, `file`, `source` and the shard count;
  // mergeSurfelParts puts the parts of every shard together into the whole file, byte for byte.
  std::optional<SurfelizeShard> shard;
  // Called after every finished array, one call at a time (never concurrently), from whichever
  // thread finished it.
  std::function<void(const SurfelizeProgress&)> onProgress{};
};

struct SurfelizeStats {
  std::uint64_t nodesWithSurfels = 0;  // nodes above the threshold (node records in the file)
  std::uint64_t arrays = 0;            // distinct arrays after sharing = captures made
  std::uint64_t surfels = 0;           // summed over the distinct arrays
  std::uint64_t candidates = 0;        // covered capture pixels, summed over the captures
  std::uint64_t arraysWritten = 0;     // arrays in the file: all of them, or a shard's own
  // The estimated seconds of the arrays made, on one core of the machine the estimate was measured on
  // (what balances shards; arrays are made on several cores at once, so a run takes less).
  double estimatedSeconds = 0.0;
  // A scene opened without its mesh arrays: the captures' decoding (the scan reads every mesh once more).
  std::uint64_t meshesDecoded = 0;
  std::uint64_t meshPeakBytesLoaded = 0;
};

// Every node above options.file.threshold gets an array of at most options.file.maxSurfels surfels in
// its own frame (see analyzeSubtree). Nodes of one subtree class (subtreeClasses) share one array,
// captured for the first of them in preorder. Arrays are made in parallel, an array captured from its
// children's surfels after them (which captures do is decided before any array is made: the children's
// drawing counted with every child array at options.file.maxSurfels surfels). Each array's ordering
// seed mixes options.file.seed with the node's stable path, so the result is the same for any thread
// count and any schedule. A scene with no node above the threshold gives a file with no arrays.
// options.file.colors picks the kept surfels' colours: their own pixel's (Pixel) or, by default, each
// one's prefilteredColors over all of its capture's candidates (Prefiltered).
SurfelFile surfelize(const Scene& scene, const Hierarchy& hierarchy, const SurfelizeOptions& options,
                     SurfelizeStats* stats = nullptr);

// surfelize straight into the .surfels file at `path`, byte for byte writeSurfelFile(path, surfelize(…)):
// each array goes to the file (SurfelFileWriter) as soon as the arrays before it are there, and its
// surfels are freed once no capture still to come may draw them, so memory follows the arrays being
// made, not the scene. On an error nothing is left under `path`.
void surfelizeToFile(const Scene& scene, const Hierarchy& hierarchy, const SurfelizeOptions& options,
                     const std::filesystem::path& path, SurfelizeStats* stats = nullptr);

// The same for a scene opened without its mesh arrays (openGltfWithoutMeshes), whose meshes `decode`
// reads: one scan reads every mesh once, a few at a time, for the fingerprints, the exact boxes and the
// areas; then each capture decodes the meshes it draws as triangles, leased for the capture, and those no
// capture holds are unloaded least recently used first beyond `cacheBytes` (a mesh that changed since the
// scan is an error naming `source` and the mesh). Memory follows the captures in flight, not the scene,
// and the file is byte for byte the one the loaded scene gives.
void surfelizeToFile(Scene& scene, const LazyMeshes::Decode& decode, std::uint64_t cacheBytes,
                     const std::string& source, const SurfelizeOptions& options, const std::filesystem::path& path,
                     SurfelizeStats* stats = nullptr);

// The positions the ordering, the colour filter and the packing values see for capture candidates.
// Surfels at one place facing opposite ways are the two sides of a thin surface (a wall, the shell of a
// cooling tower), and a renderer that culls back faces draws one of them: each side must be spread out
// on its own, or a prefix holds one side here and the other there, and culling leaves half of it open.
// So the surfels whose normal faces away from a fixed direction (not an axis: walls often are) are moved
// beside the others, three extents of the positions away along x, where the two sides never crowd each
// other out. A closed surface is split into two halves the same way, at the cost of a seam of double
// density. Stored positions stay the captured ones.
std::vector<glm::vec3> orderingPositions(std::span<const Surfel> candidates);

// How far a surfel's twin (the same surface seen from its other side) may lie, in spacings of the array.
inline constexpr double kTwinReach = 1.5;
// The sides a capture must have seen (CaptureResult::sidesSeen) for surfelize to look for twins: an open
// sheet seen from above and below has 2, a closed mesh 1 (a mesh wound half inward has 2 too, and no twins).
inline constexpr double kOpenSheetSidesSeen = 1.5;

// The share of `surfels` (those with a normal) that have a twin facing the opposite way within `reach`: about
// 1 for an open sheet captured from both sides or a shell thinner than `reach`, about 0 for a closed mesh
// (whose far side lies much farther), whatever the winding of its faces. 0 for no surfels or reach ≤ 0.
double twoSidedShare(std::span<const Surfel> surfels, double reach);

// One shard of a run split over machines, as planned (SurfelizeOptions::shard).
struct SurfelizeShardEstimate {
  std::uint64_t arraysHeld = 0;  // the arrays its part holds
  // The arrays it makes: its own, and those their captures draw that other shards hold (made again, so
  // that no shard waits on another). An array whose capture draws its children's surfels needs them, down
  // to captures of triangles: that whole group is made on one shard, and the largest such group (often the
  // root's) bounds how far a run can be split.
  std::uint64_t arraysMade = 0;
  double estimatedSeconds = 0.0;  // of the arrays made, on one core (SurfelizeStats::estimatedSeconds)
};

// How `count` shards split the arrays of surfelize(scene, hierarchy, options): per shard. `hierarchy`
// needs no boxes. Nothing is captured.
std::vector<SurfelizeShardEstimate> planSurfelizeShards(const Scene& scene, const Hierarchy& hierarchy,
                                                        const SurfelizeOptions& options, std::uint32_t count);

// An estimate of the memory surfelizeToFile needs beyond the scene itself, with `workers` arrays made
// at once: per worker a capture (G-buffer, every candidate surfel, the ordering's working set) and the
// subtree's frame; the finished arrays held at once when made one by one in index order (those that
// parents still to come capture from), plus one per worker for arrays finished ahead of the one the
// file waits for. Not a bound for every schedule: a worker far behind the others makes the file hold
// more (docs/performance.md compares it with measured peaks).
std::uint64_t surfelizeMemoryEstimate(const Scene& scene, const Hierarchy& hierarchy, const SurfelizeOptions& options,
                                      int workers);

}  // namespace pbs
