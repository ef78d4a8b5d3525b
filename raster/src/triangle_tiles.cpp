// The tile stage: one TBB task per tile walks its bin and the large-triangle bin in submission
// order, then writes depth back and resolves the winners' attributes. No two tasks share a pixel.
#include "pbs/raster/simd_clones.hpp"
#include "tile_buffer.hpp"
#include "tile_coverage.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>

namespace pbs::triangles {
namespace {

void loadTile(const Framebuffer& framebuffer, TileBuffer& tile) {
  for (int row = 0; row < tile.height; ++row) {
    float* local = tile.depth + row * kTileStride;
    const float* window = framebuffer.depth.data() + std::size_t(tile.y0 + row) * framebuffer.width + tile.x0;
    std::memcpy(local, window, std::size_t(tile.width) * sizeof(float));
    // Masked lanes past the tile's last column are still read: give them defined values.
    std::fill(local + tile.width, local + kTileStride, kClearDepth);
  }
  std::fill(tile.ids, tile.ids + tile.height * kTileStride, kNoTriangle);
}

void prefetchRaster(const TriangleBatch& batch, std::uint32_t id) {
  __builtin_prefetch(&batch.chunks[idChunk(id)].raster[idLocal(id)]);
}

// __builtin_prefetch has no effect GCC's analysis sees: it deduced that this function, when it was
// not inlined, was "pure", and deleted the call, its result unused. The records went unfetched and a
// capture ran 20 % slower. The empty volatile asm is an effect it cannot see through; it emits nothing.
void prefetchRecord(const TriangleBatch& batch, std::uint32_t id) {
  const float* record = batch.chunks[idChunk(id)].record(idLocal(id), batch.uniformStride);
  for (std::uint32_t line = 0; line < batch.maxStride(); line += 16) __builtin_prefetch(record + line);
  asm volatile("");
}

void storeTileDepth(Framebuffer& framebuffer, const TileBuffer& tile) {
  for (int row = 0; row < tile.height; ++row)
    std::memcpy(framebuffer.depth.data() + std::size_t(tile.y0 + row) * framebuffer.width + tile.x0,
                tile.depth + row * kTileStride, std::size_t(tile.width) * sizeof(float));
}

// The 8-lane coverage kernel gains from AVX-512 mask registers: about 5 % of a capture.
PBS_AVX512_CLONES
void rasterizeTile(const TriangleBatch& batch, int tileIndex) {
  const std::uint32_t* binned = batch.bins.data() + batch.binStart[tileIndex];
  const std::uint32_t* binnedEnd = batch.bins.data() + batch.binStart[tileIndex + 1];
  const std::uint32_t* large = batch.bins.data() + batch.binStart[batch.tileCount()];
  const std::uint32_t* largeEnd = batch.bins.data() + batch.binStart[batch.tileCount() + 1];
  if (binned == binnedEnd && large == largeEnd) return;

  Framebuffer& framebuffer = batch.framebuffer;
  TileBuffer tile;
  tile.x0 = tileIndex % batch.tilesX * kTileSize;
  tile.y0 = tileIndex / batch.tilesX * kTileSize;
  tile.width = std::min<int>(kTileSize, int(framebuffer.width) - tile.x0);
  tile.height = std::min<int>(kTileSize, int(framebuffer.height) - tile.y0);
  const bool resolves = framebuffer.channels != 0;
  // The tile's triangles lie scattered over the chunks' records: fetch a few ahead.
  constexpr std::ptrdiff_t kAhead = 4;
  for (const std::uint32_t* id = binned; id < binnedEnd && id < binned + kAhead; ++id) prefetchRaster(batch, *id);
  bool loaded = false;
  // Both bins are sorted by packed id, which is submission order: merge them.
  while (binned != binnedEnd || large != largeEnd) {
    const bool takeBinned = large == largeEnd || (binned != binnedEnd && *binned < *large);
    const std::uint32_t id = takeBinned ? *binned++ : *large++;
    if (binnedEnd - binned >= kAhead) prefetchRaster(batch, binned[kAhead - 1]);
    const RasterTriangle& triangle = batch.chunks[idChunk(id)].raster[idLocal(id)];
    if (!overlaps(triangle, tile)) continue;
    if (!loaded) loadTile(framebuffer, tile);
    loaded = true;
    // The resolve reads the winners' shading records once all triangles are in: fetch them now,
    // while the coverage work hides the latency.
    if (resolves) prefetchRecord(batch, id);
    rasterizeInTile(tile, triangle);
  }
  if (!loaded) return;
  storeTileDepth(framebuffer, tile);
  if (resolves) resolveTile(batch, tile);
}

}  // namespace

void rasterizeTiles(const TriangleBatch& batch) {
  tbb::parallel_for(tbb::blocked_range<int>(0, batch.tileCount(), 1), [&](const tbb::blocked_range<int>& r) {
    for (int t = r.begin(); t < r.end(); ++t) rasterizeTile(batch, t);
  });
}

}  // namespace pbs::triangles
