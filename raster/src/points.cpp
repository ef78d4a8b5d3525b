// drawPoints: points are projected and binned to tiles per chunk in parallel, then each tile is drawn by one
// task; batches bound the memory. See points_splat.hpp, points_bins.hpp and points_tile.hpp for the stages.
#include "pbs/raster/points.hpp"

#include "points_bins.hpp"
#include "points_sets.hpp"
#include "points_sizes.hpp"
#include "points_splat.hpp"
#include "points_tile.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <vector>

namespace pbs {

namespace {

using namespace points;

// A chunk is one task of projection and binning; a batch's chunks are all binned before its tiles are drawn,
// so its binned splats are in memory at once. Both are counted in points and in splat records: a splat is
// stored once per tile it overlaps, so large splats make for smaller chunks and batches. Each batch sweeps the
// framebuffer once (every tile reads and writes its pixels), so batches are large: 2^22 1-pixel points bin into
// 48 MB, and draw 12 % faster than 2^20 points did.
constexpr std::uint64_t kChunkPoints = 16384;
constexpr std::uint64_t kChunkRecords = 4 * kChunkPoints;
constexpr std::uint64_t kBatchPoints = 1u << 22;
constexpr std::uint64_t kBatchRecords = 4 * kBatchPoints;

struct Partition {
  std::uint64_t chunkPoints;
  std::uint64_t batchPoints;  // a multiple of chunkPoints
};

// Sized for the largest splat of the draw, from the number of tiles it can overlap.
Partition partition(const std::vector<float>& largestSizes, const TileGrid& grid) {
  const float largest = largestSizes.empty() ? 0.0f : *std::max_element(largestSizes.begin(), largestSizes.end());
  // A splat spans at most size + 1 pixels a side (a disc's box with its holding pixel), so at most this many
  // tiles, and never more than the grid has.
  const auto tilesAcross = [&](std::uint32_t tiles) {
    const auto span = static_cast<std::uint64_t>(std::ceil((largest + 1.0f) / float(grid.tileSize()))) + 1;
    return std::min<std::uint64_t>(span, tiles);
  };
  const std::uint64_t records = tilesAcross(grid.columns) * tilesAcross(grid.rows);
  const std::uint64_t chunkPoints = std::clamp<std::uint64_t>(kChunkRecords / records, 1, kChunkPoints);
  const std::uint64_t chunks =
      std::clamp<std::uint64_t>(kBatchRecords / (records * chunkPoints), 1, kBatchPoints / chunkPoints);
  return {chunkPoints, chunks * chunkPoints};
}

// The points a chunk projects: ordinals [begin, end) of the draw, in a batch starting at batchStart.
struct ChunkRange {
  std::uint64_t begin, end, batchStart;
};

// Calls visit(set, first index, count) for each set's part of the range, in order.
template <class Visit>
void forEachSetPart(const PointSets& sets, ChunkRange range, Visit&& visit) {
  for (std::size_t s = sets.setOf(range.begin); range.begin < range.end; ++s) {
    const std::uint64_t first = sets.first(s), size = sets.set(s).positions.size();
    const auto last = static_cast<std::size_t>(std::min(range.end - first, size));
    const auto index = static_cast<std::size_t>(range.begin - first);
    if (index < last) visit(s, index, last - index);
    range.begin = first + last;
  }
}

// Projects a chunk's points into `sorter`, keeping those that draw. When every point has drawn size 1 (or 0)
// the chunk takes the 1-pixel fast path: without sub-pixel points a largest size of at most 1 says so.
template <class Splat>
void projectChunk(const PointSets& sets, const Camera& camera, const TileGrid& grid, bool subPixel,
                  const std::vector<float>& largestSizes, ChunkRange range, ChunkSorter<Splat>& sorter) {
  constexpr bool round = std::is_same_v<Splat, DiscSplat>;
  const float smallest = subPixel ? 0.0f : 1.0f;
  bool onePixel = !subPixel;
  forEachSetPart(sets, range, [&](std::size_t s, std::size_t, std::size_t) { onePixel &= largestSizes[s] <= 1.0f; });
  alignas(64) float sizes[kBlockPoints];
  alignas(64) std::uint32_t payloads[kBlockPoints] = {};
  forEachSetPart(sets, range, [&](std::size_t s, std::size_t index, std::size_t count) {
    const PointSet& set = sets.set(s);
    const SplatProjector projector(camera, sets.clipFromObject(s), subPixel);
    for (std::size_t i = index; i < index + count; i += kBlockPoints) {
      const std::size_t n = std::min(kBlockPoints, index + count - i);
      drawnSizes(set, smallest, i, n, sizes);
      if (onePixel) {
        const auto columns = sorter.pixels();
        sets.payloads(s, i, n, range.batchStart, columns.payloads);
        projector.projectPixels(set.positions.subspan(i, n), sizes, round, grid, columns.keys);
        sorter.addPixels(n);
      } else {
        sets.payloads(s, i, n, range.batchStart, payloads);
        sorter.add(projector.project(set.positions.subspan(i, n), sizes, payloads, sorter.next()));
      }
    }
  });
}

template <class Splat>
void drawBatches(Framebuffer& framebuffer, const Camera& camera, const PointSets& sets, bool subPixel) {
  const TileGrid grid = makeTileGrid(framebuffer.width, framebuffer.height);
  std::vector<float> largestSizes(sets.size());
  for (std::size_t s = 0; s < sets.size(); ++s) largestSizes[s] = largestDrawnSize(sets.set(s), subPixel ? 0.0f : 1.0f);
  const Partition part = partition(largestSizes, grid);
  const std::uint64_t total = sets.total();
  std::vector<ChunkBins> bins((std::min(total, part.batchPoints) + part.chunkPoints - 1) / part.chunkPoints);
  tbb::enumerable_thread_specific<ChunkSorter<Splat>> sorters;
  tbb::enumerable_thread_specific<TileScratch> tileScratch;

  // Batches run one after the other, so a later batch's points are tested after an earlier batch's.
  for (std::uint64_t batchStart = 0; batchStart < total; batchStart += part.batchPoints) {
    const std::uint64_t batchEnd = std::min(total, batchStart + part.batchPoints);
    const auto chunks = static_cast<std::size_t>((batchEnd - batchStart + part.chunkPoints - 1) / part.chunkPoints);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
      ChunkSorter<Splat>& sorter = sorters.local();
      for (std::size_t c = r.begin(); c != r.end(); ++c) {
        const std::uint64_t begin = batchStart + c * part.chunkPoints;
        const std::uint64_t end = std::min(batchEnd, begin + part.chunkPoints);
        sorter.start(grid, static_cast<std::size_t>(end - begin));
        projectChunk(sets, camera, grid, subPixel, largestSizes, ChunkRange{begin, end, batchStart}, sorter);
        sorter.sort(bins[c]);
      }
    });
    const std::span<const ChunkBins> batchBins(bins.data(), chunks);
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, grid.count(), 1),
                      [&](const tbb::blocked_range<std::uint32_t>& r) {
                        TileScratch& scratch = tileScratch.local();
                        for (std::uint32_t tile = r.begin(); tile != r.end(); ++tile)
                          drawTile(framebuffer, grid, tile, batchBins, sets, batchStart, scratch);
                      });
  }
}

}  // namespace

void drawPoints(Framebuffer& framebuffer, const Camera& camera, std::span<const PointSet> sets,
                const PointOptions& options) {
  const PointSets table(framebuffer, camera, sets);
  if (table.total() == 0 || framebuffer.pixelCount() == 0) return;
  if (options.round)
    drawBatches<DiscSplat>(framebuffer, camera, table, options.subPixel);
  else
    drawBatches<SquareSplat>(framebuffer, camera, table, options.subPixel);
}

}  // namespace pbs
