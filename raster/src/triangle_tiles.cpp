// The tile stage: one TBB task per tile walks its bin and the large-triangle bin in submission
// order, then writes depth back and resolves the winners' attributes. No two tasks share a pixel.
// A pixel's id is the place of its triangle in the order the tile drew them (TileDrawn), so that the
// resolve makes the shading records of only the triangles that won a pixel, each once.
#include "pbs/raster/simd_clones.hpp"
#include "tile_buffer.hpp"
#include "tile_bins.hpp"
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

void storeTileDepth(Framebuffer& framebuffer, const TileBuffer& tile) {
  for (int row = 0; row < tile.height; ++row)
    std::memcpy(framebuffer.depth.data() + std::size_t(tile.y0 + row) * framebuffer.width + tile.x0,
                tile.depth + row * kTileStride, std::size_t(tile.width) * sizeof(float));
}

// A tile's triangles in submission order, merged from three sorted runs (tile_bins.hpp): its bin's
// copies of the triangles in this tile alone, read in one stream; its bin's ids of those in several
// tiles; and the large-triangle bin's ids. Each id is looked up in its chunk.
class TileTriangles {
 public:
  TileTriangles(const TriangleBatch& batch, int tileIndex)
      : batch_(batch),
        sole_(copiesFrom(tileIndex)),
        soleEnd_(copiesFrom(tileIndex + 1)),
        shared_(idsFrom(tileIndex)),
        sharedEnd_(idsFrom(tileIndex + 1)),
        large_(idsFrom(batch.tileCount())),
        largeEnd_(idsFrom(batch.tileCount() + 1)) {
    for (const std::uint32_t* id = shared_; id < sharedEnd_ && id < shared_ + kAhead; ++id) prefetchRaster(*id);
  }

  bool empty() const { return sole_ == soleEnd_ && shared_ == sharedEnd_ && large_ == largeEnd_; }

  // The next triangle; only while not empty().
  [[gnu::always_inline]] const RasterTriangle& next() {
    // Packed ids grow with submission order; an exhausted bin reads as kNoTriangle, above them all.
    const std::uint32_t soleId = sole_ != soleEnd_ ? sole_->id : kNoTriangle;
    const std::uint32_t sharedId = shared_ != sharedEnd_ ? *shared_ : kNoTriangle;
    const std::uint32_t largeId = large_ != largeEnd_ ? *large_ : kNoTriangle;
    if (soleId < sharedId && soleId < largeId) return *sole_++;
    std::uint32_t id;
    if (sharedId < largeId) {
      id = *shared_++;
      if (sharedEnd_ - shared_ >= kAhead) prefetchRaster(shared_[kAhead - 1]);
    } else {
      id = *large_++;
    }
    return batch_.chunks[idChunk(id)].raster[idLocal(id)];
  }

 private:
  // The ids' triangles lie scattered over the chunks: fetch a few ahead.
  static constexpr std::ptrdiff_t kAhead = 4;

  // Where bin b's copies and ids begin (the end of bin b − 1's).
  const RasterTriangle* copiesFrom(int bin) const {
    return batch_.soleTriangles.data() + copiesPart(batch_.binStart[bin]);
  }
  const std::uint32_t* idsFrom(int bin) const { return batch_.sharedIds.data() + idsPart(batch_.binStart[bin]); }
  void prefetchRaster(std::uint32_t id) const { __builtin_prefetch(&batch_.chunks[idChunk(id)].raster[idLocal(id)]); }

  const TriangleBatch& batch_;
  const RasterTriangle *sole_, *soleEnd_;
  const std::uint32_t *shared_, *sharedEnd_, *large_, *largeEnd_;
};

// Each worker thread's, reused tile after tile.
thread_local TileDrawn tileDrawn;

// The 8-lane coverage kernel gains from AVX-512 mask registers: about 5 % of a capture.
PBS_AVX512_CLONES
void rasterizeTile(const TriangleBatch& batch, int tileIndex) {
  TileTriangles triangles(batch, tileIndex);
  if (triangles.empty()) return;

  Framebuffer& framebuffer = batch.framebuffer;
  TileBuffer tile;
  tile.x0 = tileIndex % batch.tilesX * kTileSize;
  tile.y0 = tileIndex / batch.tilesX * kTileSize;
  tile.width = std::min<int>(kTileSize, int(framebuffer.width) - tile.x0);
  tile.height = std::min<int>(kTileSize, int(framebuffer.height) - tile.y0);
  const bool resolves = framebuffer.channels != 0;
  TileDrawn& drawn = tileDrawn;
  drawn.triangles.clear();
  while (!triangles.empty()) {
    const RasterTriangle& triangle = triangles.next();
    if (!overlaps(triangle, tile)) continue;
    if (drawn.triangles.empty()) loadTile(framebuffer, tile);
    rasterizeInTile(tile, triangle, std::uint32_t(drawn.triangles.size()));
    drawn.triangles.push_back(&triangle);
  }
  if (drawn.triangles.empty()) return;
  storeTileDepth(framebuffer, tile);
  if (resolves) resolveTile(batch, tile, drawn);
}

}  // namespace

void rasterizeTiles(const TriangleBatch& batch) {
  tbb::parallel_for(tbb::blocked_range<int>(0, batch.tileCount(), 1), [&](const tbb::blocked_range<int>& r) {
    for (int t = r.begin(); t < r.end(); ++t) rasterizeTile(batch, t);
  });
}

}  // namespace pbs::triangles
