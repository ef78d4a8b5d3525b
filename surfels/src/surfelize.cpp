// surfelize: one capture and ordering per distinct subtree, in parallel, largest first.
#include "pbs/surfels/surfelize.hpp"

#include "capture_from_children.hpp"
#include "surfelize_plan.hpp"

#include "pbs/raster/hash64.hpp"
#include "pbs/scene/scene_fingerprint.hpp"
#include "pbs/scene/surface_area.hpp"
#include "pbs/surfels/blue_noise_metrics.hpp"
#include "pbs/surfels/capture.hpp"
#include "pbs/surfels/ordering.hpp"
#include "pbs/surfels/prefilter_colors.hpp"
#include "pbs/surfels/surfel_nodes.hpp"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <mutex>

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

// Whether `node`'s capture draws its children's surfels (see CaptureSource).
bool captureFromChildren(const Scene& scene, const Hierarchy& frame, std::uint32_t node, CaptureSource source,
                         const detail::SurfelPlan& plan, std::span<const SurfelArray> arrays) {
  if (source == CaptureSource::Triangles) return false;
  std::uint64_t childDrawing = 0;  // splats and triangles the children's drawing would hold
  bool anyArray = false;
  for (std::uint32_t child : scene.nodes[node].children) {
    const std::uint32_t array = plan.arrayOfNode[child];
    anyArray |= array != kNoSurfels;
    childDrawing += array != kNoSurfels ? arrays[array].surfels.size() : frame.subtreeTriangles[child];
  }
  if (!anyArray) return false;
  return source == CaptureSource::ChildSurfels ||
         double(frame.subtreeTriangles[node]) > kAutoChildSurfelRatio * double(childDrawing);
}

struct MadeArray {
  SurfelArray array;
  std::uint64_t candidates = 0;
};

// The array for `node`, whose path seeds its ordering and whose subtree has `area` in its own frame.
MadeArray makeArray(const Scene& scene, std::uint32_t node, const std::string& path, double area,
                    const SurfelizeOptions& options, const detail::SurfelPlan& plan,
                    std::span<const SurfelArray> arrays) {
  const Hierarchy frame = analyzeSubtree(scene, node);
  const CaptureOptions capture{.resolution = options.file.resolution, .directions = options.file.directions};
  const bool fromChildren = captureFromChildren(scene, frame, node, options.source, plan, arrays);
  const CaptureResult captured =
      fromChildren ? detail::captureFromChildSurfels(scene, frame, node, arrays, plan.arrayOfNode, capture)
                   : captureNode(scene, frame, node, capture);

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
  array.area = area;
  array.surfels.reserve(order.size());
  for (std::uint32_t i : order) array.surfels.push_back(captured.surfels[i]);
  if (options.file.colors == SurfelColors::Prefiltered) {
    // Filtered where the ordering sees the candidates: each side of a thin surface on its own.
    const std::vector<glm::u8vec4> colors = prefilteredColors(positions, captured.surfels, order);
    for (std::size_t i = 0; i < colors.size(); ++i) array.surfels[i].color = colors[i];
  }
  array.packing = packingValue(positions, order, std::min(kPackingSample, order.size()));
  array.packingEnd = packingValue(positions, order, order.size());
  return made;
}

// Groups of arrays that can be made at the same time: all of them at once, or when children's surfels
// may be drawn one height at a time (children are lower than their parents). Each group lists the largest subtree first,
// so the longest captures start early and the small ones fill the gaps at the end.
std::vector<std::vector<std::uint32_t>> scheduleArrays(const Hierarchy& hierarchy, const detail::SurfelPlan& plan,
                                                       CaptureSource source) {
  const std::size_t arrays = plan.representative.size();
  std::vector<std::vector<std::uint32_t>> groups;
  for (std::uint32_t a = 0; a < arrays; ++a) {
    const std::size_t group = source != CaptureSource::Triangles ? plan.height[a] : 0;
    if (groups.size() <= group) groups.resize(group + 1);
    groups[group].push_back(a);
  }
  for (auto& group : groups)
    std::stable_sort(group.begin(), group.end(), [&](std::uint32_t x, std::uint32_t y) {
      return hierarchy.subtreeTriangles[plan.representative[x]] > hierarchy.subtreeTriangles[plan.representative[y]];
    });
  return groups;
}

// How many captures may draw each array: one per parent node of a representative that uses it (as
// children's surfels). None when captures draw triangles only.
std::vector<std::uint32_t> parentCaptures(const Scene& scene, const detail::SurfelPlan& plan, CaptureSource source) {
  std::vector<std::uint32_t> count(plan.representative.size(), 0);
  if (source == CaptureSource::Triangles) return count;
  for (std::uint32_t node : plan.representative)
    for (std::uint32_t child : scene.nodes[node].children)
      if (plan.arrayOfNode[child] != kNoSurfels) ++count[plan.arrayOfNode[child]];
  return count;
}

// The arrays of surfelize, each handed to `finished(index, array)` as it is made (one call at a time,
// in the order they finish). With `release`, an array is freed once handed over and no capture still
// to come may draw it.
struct ArrayMaker {
  const Scene& scene;
  const Hierarchy& hierarchy;
  const SurfelizeOptions& options;
  detail::SurfelPlan plan = detail::planSurfelArrays(scene, hierarchy, options.file.threshold);
  std::vector<std::string> paths = plan.nodes.empty() ? std::vector<std::string>() : nodePaths(scene, hierarchy);

  std::vector<SurfelNodeRecord> nodeRecords() const {
    std::vector<SurfelNodeRecord> records;
    for (std::uint32_t node : plan.nodes) records.push_back({paths[node], plan.arrayOfNode[node]});
    return records;
  }

  template <class Finished>
  std::vector<SurfelArray> make(bool release, SurfelizeStats* stats, const Finished& finished) {
    std::vector<SurfelArray> arrays(plan.representative.size());
    const std::vector<double> areas = plan.nodes.empty() ? std::vector<double>() : ownFrameSurfaceAreas(scene, hierarchy);
    std::vector<std::uint32_t> capturesLeft = parentCaptures(scene, plan, options.source);
    const auto releaseIfDone = [&](std::uint32_t a) {
      if (release && capturesLeft[a] == 0) std::vector<Surfel>().swap(arrays[a].surfels);
    };

    SurfelizeProgress progress;
    progress.arraysTotal = std::uint32_t(plan.representative.size());
    for (std::uint32_t node : plan.representative) progress.trianglesTotal += hierarchy.subtreeTriangles[node];
    std::uint64_t candidates = 0;
    std::mutex finishedMutex;

    for (const std::vector<std::uint32_t>& group : scheduleArrays(hierarchy, plan, options.source)) {
      // Workers take the next array in the group's order; each array is computed by one worker (its
      // capture runs in parallel inside), and its result goes to its own slot, so the schedule cannot
      // change the arrays.
      std::atomic<std::size_t> next{0};
      const int workers = std::max(1, std::min(tbb::this_task_arena::max_concurrency(), int(group.size())));
      tbb::parallel_for(0, workers, [&](int) {
        for (std::size_t i = next++; i < group.size(); i = next++) {
          const std::uint32_t a = group[i];
          const std::uint32_t node = plan.representative[a];
          MadeArray made = makeArray(scene, node, paths[node], areas[node], options, plan, arrays);
          const std::lock_guard lock(finishedMutex);
          arrays[a] = std::move(made.array);
          candidates += made.candidates;
          ++progress.arraysDone;
          progress.surfels += arrays[a].surfels.size();
          progress.trianglesDone += hierarchy.subtreeTriangles[node];
          finished(a, arrays[a]);
          releaseIfDone(a);
          for (std::uint32_t child : scene.nodes[node].children) {
            const std::uint32_t used = plan.arrayOfNode[child];
            if (used == kNoSurfels || capturesLeft[used] == 0) continue;
            --capturesLeft[used];
            releaseIfDone(used);
          }
          if (options.onProgress) options.onProgress(progress);
        }
      });
    }

    if (stats) {
      stats->nodesWithSurfels = plan.nodes.size();
      stats->arrays = arrays.size();
      stats->surfels = progress.surfels;
      stats->candidates = candidates;
    }
    return arrays;
  }
};

}  // namespace

std::vector<glm::vec3> orderingPositions(std::span<const Surfel> surfels) {
  const glm::vec3 side = glm::normalize(glm::vec3(0.3f, 0.8f, 0.52f));  // no axis: walls are often axis-aligned
  float extent = 0.0f;
  for (const Surfel& s : surfels) extent = std::max({extent, std::abs(s.position.x), std::abs(s.position.y), std::abs(s.position.z)});
  const glm::vec3 shift(extent > 0.0f ? 3.0f * extent : 1.0f, 0.0f, 0.0f);
  std::vector<glm::vec3> positions(surfels.size());
  for (std::size_t i = 0; i < surfels.size(); ++i)
    positions[i] = glm::dot(surfels[i].normal, side) < 0.0f ? surfels[i].position + shift : surfels[i].position;
  return positions;
}

std::uint64_t surfelizeMemoryEstimate(const Scene& scene, const Hierarchy& hierarchy, const SurfelizeOptions& options,
                                      int workers) {
  const detail::SurfelPlan plan = detail::planSurfelArrays(scene, hierarchy, options.file.threshold);
  const std::uint64_t pixels = std::uint64_t(options.file.resolution) * options.file.resolution;
  constexpr std::uint64_t kGBufferBytes = 4 + 4 + 12 + 12;  // depth, colour, position, normal per pixel
  // A candidate: the surfel, its position for the ordering, and the ordering's grid and heap entries
  // (freed before the colour filter, whose columns and cells take less).
  constexpr std::uint64_t kCandidateBytes = sizeof(Surfel) + 12 + 32;
  const std::uint64_t capture = pixels * (kGBufferBytes + options.file.directions * kCandidateBytes);
  const std::uint64_t frame = scene.nodes.size() * (sizeof(glm::dmat4) + sizeof(Bounds) + 24);
  const std::uint64_t arrays =
      std::uint64_t(plan.representative.size()) * options.file.maxSurfels * (sizeof(Surfel) + kSurfelBytes);
  return std::uint64_t(std::max(workers, 1)) * (capture + frame) + arrays;
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
  ArrayMaker maker{scene, hierarchy, options};
  SurfelFile file;
  file.sceneFingerprint = sceneFingerprint(scene);
  file.options = options.file;
  file.nodes = maker.nodeRecords();
  file.arrays = maker.make(false, stats, [](std::uint32_t, const SurfelArray&) {});
  return file;
}

void surfelizeToFile(const Scene& scene, const Hierarchy& hierarchy, const SurfelizeOptions& options,
                     const std::filesystem::path& path, SurfelizeStats* stats) {
  ArrayMaker maker{scene, hierarchy, options};
  SurfelFileWriter writer(path, sceneFingerprint(scene), options.file, maker.nodeRecords(),
                          std::uint32_t(maker.plan.representative.size()));
  maker.make(true, stats, [&](std::uint32_t a, const SurfelArray& array) { writer.add(a, array); });
  writer.finish();
}

}  // namespace pbs
