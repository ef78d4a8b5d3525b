// SurfelStream: a simulated link that delivers the chunks and meshes a view lacks, the most missing pixels
// per byte first.
#include "pbs/surfels/surfel_stream.hpp"

#include <pbs/raster/projected_box.hpp>
#include <pbs/raster/value_names.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <stdexcept>
#include <utility>

namespace pbs {
namespace {

constexpr ValueNames<StreamOrder, 2> kOrderNames{
    {{{StreamOrder::Prefixes, "prefixes"}, {StreamOrder::WholeArrays, "arrays"}}}};

constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

// The loaded length once `count` surfels are read in whole chunks (or the array ends).
std::size_t wholeChunks(std::size_t count, std::size_t size) {
  return std::min(size, (count + kSurfelsPerChunk - 1) / kSurfelsPerChunk * kSurfelsPerChunk);
}

}  // namespace

std::optional<StreamOrder> streamOrderFromName(std::string_view name) { return kOrderNames.parse(name); }

const char* streamOrderName(StreamOrder order) { return kOrderNames.name(order).data(); }

struct SurfelStream::Need {
  bool mesh = false;
  std::uint32_t index = 0;  // of the array or the mesh
  // An array: each draw's prefix length and point size in pixels.
  std::vector<std::pair<std::uint32_t, double>> prefixes;
  double boxPixels = 0.0;  // a mesh: the projected box areas of the nodes that draw it
};

SurfelStream::SurfelStream(SurfelCache& cache, const Scene& scene, const Hierarchy& hierarchy, const LodOptions& lod,
                           const StreamOptions& options)
    : cache_(cache),
      scene_(scene),
      hierarchy_(hierarchy),
      lod_(lod),
      options_(options),
      meshArrived_(scene.meshes.size(), 0) {
  if (!(options.bytesPerSecond > 0.0) || !std::isfinite(options.bytesPerSecond))
    throw std::invalid_argument("a stream needs a positive, finite bandwidth");
  // The threshold's cut: a link delivers meshes last, so it plans for surfels, as FrameRenderer draws a stream.
  lod_.descendWhereRaysCheaper = false;
}

std::vector<SurfelStream::Need> SurfelStream::needsOf(const LodDraws& draws, const Camera& camera) const {
  std::vector<Need> needs;
  std::vector<std::size_t> ofArray(cache_.surfels().arrays.size(), kNone), ofMesh(scene_.meshes.size(), kNone);
  auto needOf = [&](std::vector<std::size_t>& of, std::uint32_t index, bool mesh) -> Need& {
    if (of[index] == kNone) {
      of[index] = needs.size();
      needs.push_back({.mesh = mesh, .index = index, .prefixes = {}, .boxPixels = 0.0});
    }
    return needs[of[index]];
  };
  for (const LodDraws::Surfels& draw : draws.surfels)
    needOf(ofArray, draw.array, false).prefixes.emplace_back(draw.count, draw.pointSize);
  for (const LodDraws::Surfels& draw : standIns(draws, camera))
    needOf(ofArray, draw.array, false).prefixes.emplace_back(draw.count, draw.pointSize);
  for (std::uint32_t node : draws.geometryNodes)
    needOf(ofMesh, std::uint32_t(scene_.nodes[node].mesh), true).boxPixels +=
        projectedBoxPixels(camera, hierarchy_.worldBounds[node]);
  return needs;
}

std::vector<LodDraws::Surfels> SurfelStream::standIns(const LodDraws& draws, const Camera& camera) const {
  const SceneSurfels& surfels = cache_.surfels();
  auto hasArray = [&](std::int32_t node) {
    return std::size_t(node) < surfels.arrayOfNode.size() && surfels.arrayOfNode[std::size_t(node)] != kNoSurfels;
  };
  std::vector<std::uint32_t> nodes;
  for (std::uint32_t node : draws.geometryNodes) {
    if (meshArrived_[std::size_t(scene_.nodes[node].mesh)]) continue;
    std::int32_t n = std::int32_t(node);
    while (n >= 0 && !hasArray(n)) n = hierarchy_.parent[std::size_t(n)];
    if (n >= 0) nodes.push_back(std::uint32_t(n));
  }
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  std::vector<LodDraws::Surfels> drawn;
  for (std::uint32_t node : nodes) {
    const bool inDraws = std::any_of(draws.surfels.begin(), draws.surfels.end(),
                                     [node](const LodDraws::Surfels& d) { return d.node == node; });
    if (inDraws) continue;
    if (auto draw = wholeArrayDraw(scene_, hierarchy_, surfels, camera, lod_, node)) drawn.push_back(*draw);
  }
  return drawn;
}

double SurfelStream::missingPixels(const Need& need, std::size_t upTo) const {
  if (need.mesh) return meshArrived_[need.index] ? 0.0 : need.boxPixels;
  const std::size_t loaded = cache_.surfels().arrays[need.index].loaded();
  double pixels = 0.0;
  for (const auto& [count, pointSize] : need.prefixes) {
    const std::size_t wanted = std::min<std::size_t>(count, upTo);
    if (wanted > loaded) pixels += double(wanted - loaded) * pointSize * pointSize;
  }
  return pixels;
}

std::size_t SurfelStream::nextLength(const Need& need) const {
  const SplatArray& splats = cache_.surfels().arrays[need.index];
  return options_.order == StreamOrder::Prefixes ? wholeChunks(splats.loaded() + 1, splats.size()) : splats.size();
}

std::uint64_t SurfelStream::nextTransferBytes(const Need& need) const {
  if (need.mesh) return meshBytes(scene_.meshes[need.index]);
  return cache_.storedBytes(need.index, nextLength(need) - cache_.surfels().arrays[need.index].loaded());
}

double SurfelStream::gainPerByte(const Need& need) const {
  const double pixels = missingPixels(need, need.mesh ? 0 : nextLength(need));
  return pixels > 0.0 ? pixels / double(std::max<std::uint64_t>(1, nextTransferBytes(need))) : 0.0;
}

void SurfelStream::transfer(const Need& need, std::uint64_t bytes) {
  if (need.mesh) {
    meshArrived_[need.index] = 1;
    stats_.meshBytes += bytes;
  } else {
    cache_.loadPrefix(need.index, nextLength(need));
    stats_.surfelBytes += bytes;
  }
  stats_.bytes += bytes;
}

void SurfelStream::advance(const Camera& camera, double seconds) {
  if (!(seconds >= 0.0)) throw std::invalid_argument("a stream's clock cannot go back");
  stats_.seconds += seconds;
  credit_ += seconds * options_.bytesPerSecond;
  if (!stats_.tablesArrived) {
    const double tables = double(cache_.tablesBytes());
    if (credit_ < tables) {
      stats_.missingBytes = cache_.tablesBytes();  // what the view lacks beyond them is not known yet
      return;
    }
    credit_ -= tables;
    stats_.bytes += cache_.tablesBytes();
    stats_.tablesArrived = true;
  }
  const LodDraws draws = traverseLod(scene_, hierarchy_, cache_.surfels(), camera, lod_);
  const std::vector<Need> needs = needsOf(draws, camera);
  // The transfer that fills the most missing pixels per byte first; on a tie the need met first in the
  // traversal. (By pixels alone a large mesh would hold the link while many small chunks wait.)
  using Entry = std::pair<double, std::size_t>;
  auto lessUseful = [](const Entry& a, const Entry& b) {
    return a.first < b.first || (a.first == b.first && a.second > b.second);
  };
  std::priority_queue<Entry, std::vector<Entry>, decltype(lessUseful)> queue(lessUseful);
  for (std::size_t i = 0; i < needs.size(); ++i)
    if (const double gain = gainPerByte(needs[i]); gain > 0.0) queue.emplace(gain, i);
  while (!queue.empty()) {
    const std::size_t i = queue.top().second;
    const std::uint64_t bytes = nextTransferBytes(needs[i]);
    if (double(bytes) > credit_) break;  // the link is busy with it until the next advance
    queue.pop();
    credit_ -= double(bytes);
    transfer(needs[i], bytes);
    if (const double gain = gainPerByte(needs[i]); gain > 0.0) queue.emplace(gain, i);
  }
  if (queue.empty()) credit_ = 0.0;

  stats_.missingBytes = 0;
  stats_.missingPixels = 0.0;
  for (const Need& need : needs) {
    const double pixels = missingPixels(need, std::numeric_limits<std::size_t>::max());
    if (!(pixels > 0.0)) continue;
    stats_.missingPixels += pixels;
    if (need.mesh) {
      stats_.missingBytes += meshBytes(scene_.meshes[need.index]);
    } else {
      const SplatArray& splats = cache_.surfels().arrays[need.index];
      std::size_t longest = 0;
      for (const auto& [count, pointSize] : need.prefixes) longest = std::max<std::size_t>(longest, count);
      const std::size_t end =
          options_.order == StreamOrder::Prefixes ? wholeChunks(longest, splats.size()) : splats.size();
      stats_.missingBytes += cache_.storedBytes(need.index, end - splats.loaded());
    }
  }
  cache_.keep(draws);
}

LodDraws SurfelStream::arrived(const LodDraws& draws, const Camera& camera) const {
  LodDraws cut;
  if (!stats_.tablesArrived) return cut;
  for (std::uint32_t node : draws.geometryNodes) {
    const std::size_t mesh = std::size_t(scene_.nodes[node].mesh);
    if (!meshArrived_[mesh]) continue;
    cut.geometryNodes.push_back(node);
    cut.triangles += scene_.meshes[mesh].triangleCount();
  }
  std::vector<LodDraws::Surfels> wanted = draws.surfels;
  for (const LodDraws::Surfels& draw : standIns(draws, camera)) wanted.push_back(draw);
  for (const LodDraws::Surfels& draw : wanted) {
    const SplatArray& splats = cache_.surfels().arrays[draw.array];
    LodDraws::Surfels kept = draw;
    kept.count = std::uint32_t(std::min<std::size_t>(draw.count, splats.loaded()));
    if (kept.count == 0) continue;
    // Fewer surfels than the size asks for: larger discs close the surface, as for an exhausted array.
    const double closing = splats.packing > 0.0 ? splats.spacing(kept.count) : draw.radius;
    if (kept.count < draw.count && closing > draw.radius && draw.radius > 0.0) {
      kept.pointSize = draw.pointSize * closing / draw.radius;
      kept.radius = closing;
    }
    cut.surfels.push_back(kept);
    cut.surfelCount += kept.count;
  }
  return cut;
}

}  // namespace pbs
