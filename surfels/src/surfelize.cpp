// surfelize: one capture and ordering per distinct subtree, in parallel, largest first.
#include "pbs/surfels/surfelize.hpp"

#include "capture_from_children.hpp"
#include "order_nearest_grid.hpp"
#include "surfelize_plan.hpp"
#include "surfelize_shards.hpp"

#include "pbs/raster/hash64.hpp"
#include "pbs/raster/raster_limits.hpp"
#include "pbs/scene/scene_draws.hpp"
#include "pbs/scene/scene_fingerprint.hpp"
#include "pbs/scene/scene_scan.hpp"
#include "pbs/surfels/blue_noise_metrics.hpp"
#include "pbs/surfels/capture.hpp"
#include "pbs/surfels/ordering.hpp"
#include "pbs/surfels/prefilter_colors.hpp"
#include "pbs/surfels/surfel_nodes.hpp"

#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <functional>
#include <mutex>
#include <numeric>
#include <queue>

namespace pbs {
namespace {

// The packing value the renderer sizes prefixes with: d_k² · k for the mean nearest-neighbour distance
// d_k of the first k ordered points. Spacing shrinks as 1/sqrt(count) on a surface, so packing / r² is
// the count whose spacing is r, for any r.
double packingValue(std::span<const glm::vec3> positions, std::span<const std::uint32_t> order, std::size_t k) {
  if (k < 2) return 0.0;
  const double spacing = meanNearestNeighbourDistance(positions, order, k);
  return spacing * spacing * double(k);
}

// The two-sided share of an array captured from triangles. Twins lie within about one spacing of each
// other. Only a capture that saw back faces holds an open sheet: a closed mesh wound consistently is seen
// from outside alone, and a shell thinner than the spacing then keeps its two sides apart by culling
// (drawn facing either way, its inner side showed through its outer one: default scene, orbit, FLIP 0.128
// → 0.154).
double twoSidedShareOfTriangles(const CaptureResult& captured, const SurfelArray& array) {
  if (captured.sidesSeen() < kOpenSheetSidesSeen || array.surfels.size() < 2) return 0.0;
  const double spacing = std::sqrt(array.packingEnd / double(array.surfels.size()));
  return twoSidedShare(array.surfels, kTwinReach * spacing);
}

// An array captured from its children's surfels is an open sheet as far as they are: the mean of their
// arrays' shares. Its own capture cannot tell, since it draws the children's splats facing either way
// and so sees the backs of closed children too (the default scene's root: sides seen over 1.5).
double meanTwoSidedShare(std::span<const SurfelArray> arrays, std::span<const std::uint32_t> children) {
  if (children.empty()) return 0.0;
  double sum = 0.0;
  for (std::uint32_t c : children) sum += arrays[c].twoSidedShare;
  return sum / double(children.size());
}

struct MadeArray {
  SurfelArray array;
  std::uint64_t candidates = 0;
};

// The capture of `node` (from its children's surfels or not, as the plan says) in its subtree's frame
// `frame`, leaving out the faces that `meshClosures` (per mesh) says face inside a closed mesh. With `meshes` (a scene
// opened without its mesh arrays), the meshes it draws as triangles are leased for the capture alone.
CaptureResult captureArray(const Scene& scene, const Hierarchy& frame, std::uint32_t node, bool fromChildren,
                           const SurfelizeOptions& options, const detail::SurfelPlan& plan,
                           std::span<const SurfelArray> arrays, std::span<const MeshClosure> meshClosures,
                           LazyMeshes* meshes) {
  const CaptureOptions capture{
      .resolution = options.file.resolution, .directions = options.file.directions, .meshClosures = meshClosures};
  LazyMeshes::Lease lease;
  if (meshes)
    lease = meshes->requireDrawnBy(fromChildren ? detail::childCaptureTriangleNodes(scene, node, plan.arrayOfNode)
                                                : subtreeNodes(scene, node));
  return fromChildren ? detail::captureFromChildSurfels(scene, frame, node, arrays, plan.arrayOfNode, capture)
                      : captureNode(scene, frame, node, capture);
}

// Array `a`, captured for its representative, whose path seeds its ordering and whose subtree has `area`
// in its own frame.
MadeArray makeArray(const Scene& scene, std::uint32_t a, std::span<const Bounds> boxes, const std::string& path,
                    double area, const SurfelizeOptions& options, const detail::SurfelPlan& plan,
                    std::span<const SurfelArray> arrays, std::span<const MeshClosure> meshClosures,
                    LazyMeshes* meshes) {
  const std::uint32_t node = plan.representative[a];
  const Hierarchy frame = analyzeSubtree(scene, node, boxes);
  const CaptureResult captured =
      captureArray(scene, frame, node, plan.fromChildren[a], options, plan, arrays, meshClosures, meshes);
  if (meshes) meshes->unloadOverBudget();

  const std::vector<glm::vec3> positions = orderingPositions(captured.surfels);
  Hash64 seed(options.file.seed);
  seed.string(path);
  const std::vector<std::uint32_t> order =
      orderPoints(options.file.ordering, positions, options.file.maxSurfels, seed.digest());

  MadeArray made;
  made.candidates = captured.surfels.size();
  SurfelArray& array = made.array;
  array.box = frame.worldBounds[node];
  array.coverage = captured.coverage;
  // The surface the surfels stand for, per side seen: an open sheet captured from both sides has half its
  // surfels on each (the cap on the renderer's packing values).
  array.area = area * captured.sidesSeen();
  array.surfels.reserve(order.size());
  for (std::uint32_t i : order) array.surfels.push_back(captured.surfels[i]);
  if (options.file.colors == SurfelColors::Prefiltered) {
    // Filtered where the ordering sees the candidates: each side of a thin surface on its own.
    const std::vector<glm::u8vec4> colors = prefilteredColors(positions, captured.surfels, order);
    for (std::size_t i = 0; i < colors.size(); ++i) array.surfels[i].color = colors[i];
  }
  array.packing = packingValue(positions, order, std::min(kPackingSample, order.size()));
  array.packingEnd = packingValue(positions, order, order.size());
  array.twoSidedShare = float(plan.fromChildren[a] ? meanTwoSidedShare(arrays, plan.childArrays[a])
                                                   : twoSidedShareOfTriangles(captured, array));
  return made;
}

// The most arrays held at once when they are made one at a time in index order, as the schedule below
// does with one worker (children are numbered before their parents, so the lowest ready array is
// always the next index): an array stays from when it is made until the last parent that captures
// from it is.
std::uint64_t arraysHeldInIndexOrder(const std::vector<std::vector<std::uint32_t>>& children) {
  const std::size_t count = children.size();
  std::vector<std::size_t> lastUse(count);
  for (std::size_t a = 0; a < count; ++a) lastUse[a] = a;
  for (std::size_t a = 0; a < count; ++a)
    for (std::uint32_t child : children[a]) lastUse[child] = std::max(lastUse[child], a);
  std::vector<std::int64_t> change(count + 1, 0);  // held counts change at these steps
  for (std::size_t a = 0; a < count; ++a) {
    if (lastUse[a] == a) continue;  // written and freed at once
    ++change[a];
    --change[lastUse[a] + 1];
  }
  std::int64_t held = 0, peak = 0;
  for (std::size_t step = 0; step < count; ++step) peak = std::max(peak, held += change[step]);
  return std::uint64_t(peak);
}

// The arrays of surfelize, each handed to `finished(index, array)` as it is made (one call at a time,
// in the order they finish). With `release`, an array is freed once handed over and no capture still
// to come may draw it. What needs the vertices beside the captures comes from one scan of the meshes,
// read by `read`; `hierarchy` needs no boxes (analyzeStructure's will do). With `meshes`, the scene's
// mesh arrays are not loaded and each capture loads those it draws.
struct ArrayMaker {
  ArrayMaker(const Scene& scene, const Hierarchy& hierarchy, const SurfelizeOptions& options, const MeshReader& read,
             bool worldBounds)
      : scene(scene),
        hierarchy(hierarchy),
        options(options),
        plan(detail::planSurfelArrays(scene, hierarchy, options)),
        paths(plan.nodes.empty() ? std::vector<std::string>() : nodePaths(scene, hierarchy)),
        scan(scanScene(scene, hierarchy,
                       {.worldBounds = worldBounds,
                        .subtreeStarts = plan.representative,
                        .ownFrameAreas = !plan.nodes.empty(),
                        .meshClosures = !plan.nodes.empty()},
                       read)) {}

  const Scene& scene;
  const Hierarchy& hierarchy;
  const SurfelizeOptions& options;
  detail::SurfelPlan plan;
  std::vector<std::string> paths;
  SceneScan scan;
  LazyMeshes* meshes = nullptr;

  // The scene table, with the world boxes of `instanceBounds` (analyzeHierarchy's).
  SurfelSceneTable sceneTable(std::span<const Bounds> instanceBounds) const {
    return {.structure = structureFingerprint(scene),
            .meshes = scan.meshFingerprints,
            .instanceBounds = std::vector<Bounds>(instanceBounds.begin(), instanceBounds.end())};
  }

  std::vector<SurfelNodeRecord> nodeRecords() const {
    std::vector<SurfelNodeRecord> records;
    for (std::uint32_t node : plan.nodes) records.push_back({paths[node], plan.arrayOfNode[node]});
    return records;
  }

  // Every array's index, in order: what a whole run makes.
  std::vector<std::uint32_t> allArrays() const {
    std::vector<std::uint32_t> all(plan.representative.size());
    std::iota(all.begin(), all.end(), 0u);
    return all;
  }

  // The arrays `wanted`, which must hold every array a wanted one's capture draws. Workers take the lowest-numbered
  // array whose children's arrays are made (children first, so in about index order: few finished arrays wait for their
  // parents or for the file). Each array is made by one worker (its capture runs in parallel inside) into its own slot,
  // so the schedule cannot change the arrays.
  template <class Finished>
  std::vector<SurfelArray> make(std::span<const std::uint32_t> wanted, bool release, SurfelizeStats* stats,
                                const Finished& finished) {
    const std::size_t count = plan.representative.size();
    std::vector<SurfelArray> arrays(count);
    const std::vector<double>& areas = scan.ownFrameAreas;
    const std::vector<std::vector<std::uint32_t>>& children = plan.childArrays;
    std::vector<std::vector<std::uint32_t>> parents(count);
    std::vector<std::uint32_t> childrenLeft(count), capturesLeft(count, 0);
    for (std::uint32_t a : wanted) {
      childrenLeft[a] = std::uint32_t(children[a].size());
      for (std::uint32_t child : children[a]) parents[child].push_back(a), ++capturesLeft[child];
    }
    std::priority_queue<std::uint32_t, std::vector<std::uint32_t>, std::greater<>> ready;
    for (std::uint32_t a : wanted)
      if (childrenLeft[a] == 0) ready.push(a);
    const auto releaseIfDone = [&](std::uint32_t a) {
      if (release && capturesLeft[a] == 0) std::vector<Surfel>().swap(arrays[a].surfels);
    };

    SurfelizeProgress progress;
    progress.arraysTotal = std::uint32_t(wanted.size());
    for (std::uint32_t a : wanted) progress.trianglesTotal += hierarchy.subtreeTriangles[plan.representative[a]];
    std::uint64_t candidates = 0;
    // Under `mutex`: the ready queue, the counts above, the progress, `finished`. No task ever waits
    // on another (a thread waiting inside a capture's parallel loop may run a task on top of it): a
    // task takes ready arrays until there are none, and a finished array that readies more starts
    // tasks for them, up to `workers`.
    std::mutex mutex;
    std::size_t running = 0;
    bool failed = false;  // a task threw: the others stop taking arrays
    const std::size_t workers = std::size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
    tbb::task_group tasks;
    std::function<void()> work;
    const auto startTasks = [&](std::size_t busy) {  // under `mutex`; `busy` running tasks take no more
      for (std::size_t spare = ready.size() > busy ? ready.size() - busy : 0; spare > 0 && running < workers; --spare) {
        ++running;
        tasks.run(work);
      }
    };
    work = [&] {
      for (;;) {
        std::uint32_t a = 0;
        {
          const std::lock_guard lock(mutex);
          if (failed || ready.empty()) {
            --running;
            return;
          }
          a = ready.top();
          ready.pop();
        }
        try {
          const std::uint32_t node = plan.representative[a];
          MadeArray made = makeArray(scene, a, scan.subtreeBounds[a], paths[node], areas[node], options, plan, arrays,
                                     scan.meshClosures, meshes);
          const std::lock_guard lock(mutex);
          arrays[a] = std::move(made.array);
          candidates += made.candidates;
          ++progress.arraysDone;
          progress.surfels += arrays[a].surfels.size();
          progress.trianglesDone += hierarchy.subtreeTriangles[node];
          finished(a, arrays[a]);
          releaseIfDone(a);
          for (std::uint32_t child : children[a]) {
            --capturesLeft[child];
            releaseIfDone(child);
          }
          for (std::uint32_t parent : parents[a])
            if (--childrenLeft[parent] == 0) ready.push(parent);
          if (options.onProgress) options.onProgress(progress);
          startTasks(1);  // this task takes the next ready array itself
        } catch (...) {
          const std::lock_guard lock(mutex);
          failed = true;
          --running;
          throw;
        }
      }
    };
    {
      const std::lock_guard lock(mutex);
      startTasks(0);
    }
    tasks.wait();

    if (stats) {
      stats->nodesWithSurfels = plan.nodes.size();
      stats->arrays = wanted.size();
      stats->surfels = progress.surfels;
      stats->candidates = candidates;
      stats->arraysWritten = wanted.size();
      stats->estimatedSeconds = 0.0;
      for (std::uint32_t a : wanted)
        stats->estimatedSeconds += detail::estimatedArraySeconds(options, plan.primitivesDrawn[a]);
    }
    return arrays;
  }
};

}  // namespace

double twoSidedShare(std::span<const Surfel> surfels, double reach) {
  if (surfels.empty() || !(reach > 0.0) || !std::isfinite(reach)) return 0.0;
  // Each surfel is looked up at p − 2·reach·n among the others placed at p' + 2·reach·n': a twin (p' near p,
  // n' = −n) lands within reach of it, a neighbour on the same side about 4·reach away.
  const auto lift = float(2.0 * reach);
  std::vector<glm::vec3> lifted(surfels.size());
  for (std::size_t i = 0; i < surfels.size(); ++i) lifted[i] = surfels[i].position + lift * surfels[i].normal;
  NearestPointGrid grid(lifted, "twoSidedShare");
  for (std::uint32_t i = 0; i < surfels.size(); ++i) grid.insert(i);
  const auto reach2 = float(reach * reach);
  std::size_t facing = 0, twins = 0;
  for (std::uint32_t i = 0; i < surfels.size(); ++i) {
    if (surfels[i].normal == glm::vec3(0.0f)) continue;
    ++facing;
    twins += grid.nearestSquared(surfels[i].position - lift * surfels[i].normal, i, reach2) <= reach2;
  }
  return facing > 0 ? double(twins) / double(facing) : 0.0;
}

std::vector<glm::vec3> orderingPositions(std::span<const Surfel> surfels) {
  const glm::vec3 side = glm::normalize(glm::vec3(0.3f, 0.8f, 0.52f));  // no axis: walls are often axis-aligned
  float extent = 0.0f;
  for (const Surfel& s : surfels)
    extent = std::max({extent, std::abs(s.position.x), std::abs(s.position.y), std::abs(s.position.z)});
  const glm::vec3 shift(extent > 0.0f ? 3.0f * extent : 1.0f, 0.0f, 0.0f);
  std::vector<glm::vec3> positions(surfels.size());
  for (std::size_t i = 0; i < surfels.size(); ++i)
    positions[i] = glm::dot(surfels[i].normal, side) < 0.0f ? surfels[i].position + shift : surfels[i].position;
  return positions;
}

std::uint64_t surfelizeMemoryEstimate(const Scene& scene, const Hierarchy& hierarchy, const SurfelizeOptions& options,
                                      int workers) {
  const detail::SurfelPlan plan = detail::planSurfelArrays(scene, hierarchy, options);
  const std::uint64_t pixels = std::uint64_t(options.file.resolution) * options.file.resolution;
  // The G-buffers of the views each capture draws at once.
  const std::uint64_t gbuffers = concurrentCaptureViews(options.file.directions, pixels, workers);
  // A candidate: the surfel, its position for the ordering, and the ordering's grid and heap entries
  // (freed before the colour filter, whose columns and cells take less).
  constexpr std::uint64_t kCandidateBytes = sizeof(Surfel) + 12 + 32;
  const std::uint64_t capture = pixels * (gbuffers * kCaptureBytesPerPixel + options.file.directions * kCandidateBytes);
  const std::uint64_t frame = scene.nodes.size() * (sizeof(glm::dmat4) + sizeof(Bounds) + 24);
  // The rasterizer's working memory, which each worker keeps between captures: a batch of the largest
  // capture's triangles at most.
  const std::uint64_t mostDrawn =
      plan.primitivesDrawn.empty() ? 0 : *std::max_element(plan.primitivesDrawn.begin(), plan.primitivesDrawn.end());
  const std::uint64_t rasterizer =
      std::min<std::uint64_t>(mostDrawn * kTriangleBufferBytesPerTriangle, kKeptTriangleBufferBytes);
  // An array decoded and encoded for the file. Besides the arrays being made, held are those that
  // parents still to come capture from, and those finished ahead of an earlier one the file waits for.
  const std::uint64_t array = std::uint64_t(options.file.maxSurfels) * (sizeof(Surfel) + kSurfelBytes);
  const std::uint64_t held = arraysHeldInIndexOrder(plan.childArrays) + std::uint64_t(std::max(workers, 1));
  const std::uint64_t arrays = std::min<std::uint64_t>(held, plan.representative.size()) * array;
  return std::uint64_t(std::max(workers, 1)) * (capture + frame + rasterizer) + arrays +
         plan.representative.size() * sizeof(SurfelArray);
}

std::vector<SurfelizeShardEstimate> planSurfelizeShards(const Scene& scene, const Hierarchy& hierarchy,
                                                        const SurfelizeOptions& options, std::uint32_t count) {
  const detail::SurfelPlan plan = detail::planSurfelArrays(scene, hierarchy, options);
  const detail::ShardPlan shards = detail::planShards(plan, options, count);
  std::vector<SurfelizeShardEstimate> estimates(count);
  for (std::uint32_t owner : shards.owner) ++estimates[owner].arraysHeld;
  for (std::uint32_t s = 0; s < count; ++s) {
    estimates[s].arraysMade = shards.made[s].size();
    estimates[s].estimatedSeconds = shards.shardSeconds[s];
  }
  return estimates;
}

std::string_view captureSourceName(CaptureSource source) {
  switch (source) {
    case CaptureSource::Triangles: return "triangles";
    case CaptureSource::ChildSurfels: return "children";
    case CaptureSource::Auto: return "auto";
  }
  return "unknown";
}

SurfelFile surfelize(const Scene& scene, const Hierarchy& hierarchy, const SurfelizeOptions& options,
                     SurfelizeStats* stats) {
  ArrayMaker maker(scene, hierarchy, options, loadedMeshes(scene), false);
  SurfelFile file;
  file.sceneFingerprint = maker.scan.sceneFingerprint;
  file.options = options.file;
  file.nodes = maker.nodeRecords();
  file.sceneTable = maker.sceneTable(hierarchy.instanceBounds);
  file.arrays = maker.make(maker.allArrays(), false, stats, [](std::uint32_t, const SurfelArray&) {});
  return file;
}

namespace {

// The streaming writer fed by `maker`, with the scene table's world boxes `instanceBounds`: the whole
// file, or with options.shard that shard's part (the arrays of other shards empty, those it makes again
// for its own captures left out).
void writeArrays(ArrayMaker& maker, std::span<const Bounds> instanceBounds, const std::filesystem::path& path,
                 SurfelizeStats* stats) {
  const auto arrays = std::uint32_t(maker.plan.representative.size());
  if (!maker.options.shard) {
    SurfelFileWriter writer(path, maker.scan.sceneFingerprint, maker.options.file, maker.nodeRecords(),
                            maker.sceneTable(instanceBounds), arrays);
    maker.make(maker.allArrays(), true, stats,
               [&](std::uint32_t a, const SurfelArray& array) { writer.add(a, array); });
    writer.finish();
    return;
  }
  const SurfelizeShard shard = *maker.options.shard;
  const detail::ShardPlan plan = detail::planShards(maker.plan, maker.options, shard.count);
  SurfelShardTable table{.index = shard.index, .count = shard.count, .plan = plan.identity, .arrays = {}};
  for (std::uint32_t a = 0; a < arrays; ++a)
    if (plan.owner[a] == shard.index) table.arrays.push_back(a);
  const std::size_t held = table.arrays.size();
  SurfelFileWriter writer(path, maker.scan.sceneFingerprint, maker.options.file, maker.nodeRecords(),
                          maker.sceneTable(instanceBounds), arrays, std::move(table));
  SurfelArray empty;  // what a part holds of another shard's array: no surfels, a box that is finite
  empty.box = Bounds{glm::dvec3(0.0), glm::dvec3(0.0)};
  for (std::uint32_t a = 0; a < arrays; ++a)
    if (plan.owner[a] != shard.index) writer.add(a, empty);
  maker.make(plan.made[shard.index], true, stats, [&](std::uint32_t a, const SurfelArray& array) {
    if (plan.owner[a] == shard.index) writer.add(a, array);
  });
  writer.finish();
  if (stats) stats->arraysWritten = held;
}

}  // namespace

void surfelizeToFile(const Scene& scene, const Hierarchy& hierarchy, const SurfelizeOptions& options,
                     const std::filesystem::path& path, SurfelizeStats* stats) {
  ArrayMaker maker(scene, hierarchy, options, loadedMeshes(scene), false);
  writeArrays(maker, hierarchy.instanceBounds, path, stats);
}

void surfelizeToFile(Scene& scene, const LazyMeshes::Decode& decode, std::uint64_t cacheBytes,
                     const std::string& source, const SurfelizeOptions& options, const std::filesystem::path& path,
                     SurfelizeStats* stats) {
  const Hierarchy structure = analyzeStructure(scene);
  const MeshReader read = [&](std::uint32_t mesh) { return std::make_shared<const Mesh>(decode(mesh)); };
  ArrayMaker maker(scene, structure, options, read, true);
  LazyMeshes meshes(scene, decode, maker.scan.meshFingerprints, source, cacheBytes);
  maker.meshes = &meshes;
  writeArrays(maker, maker.scan.instanceBounds, path, stats);
  if (stats) {
    stats->meshesDecoded = meshes.stats().decoded;
    stats->meshPeakBytesLoaded = meshes.stats().peakBytesLoaded;
  }
}

}  // namespace pbs
