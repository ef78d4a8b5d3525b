// The per-chunk counting sort of splats by tile.
#include "points_bins.hpp"

#include <algorithm>
#include <cassert>

namespace pbs::points {

namespace {

template <class Visit>
void forEachTile(const TileGrid& grid, const SquareSplat& splat, Visit&& visit) {
  const std::uint32_t tx0 = splat.x0 >> grid.shift, tx1 = (splat.x1 - 1u) >> grid.shift;
  const std::uint32_t ty0 = splat.y0 >> grid.shift, ty1 = (splat.y1 - 1u) >> grid.shift;
  for (std::uint32_t ty = ty0; ty <= ty1; ++ty)
    for (std::uint32_t tx = tx0; tx <= tx1; ++tx) visit(ty * grid.columns + tx);
}

UninitializedVector<SquareSplat>& binsOf(ChunkBins& bins, const SquareSplat*) {
  bins.kind = BinKind::squares;
  return bins.squares;
}
UninitializedVector<DiscSplat>& binsOf(ChunkBins& bins, const DiscSplat*) {
  bins.kind = BinKind::discs;
  return bins.discs;
}

}  // namespace

template <class Splat>
void ChunkSorter<Splat>::start(const TileGrid& grid, std::size_t points) {
  grid_ = &grid;
  sized(splats_, points);
  sized(keys_, points);
  sized(depths_, points);
  sized(payloads_, points);
  counts_.assign(grid.count() + 1, 0);
  size_ = 0;
  pixelCount_ = 0;
  single_ = true;
}

template <class Splat>
void ChunkSorter<Splat>::add(std::size_t count) {
  const TileGrid& grid = *grid_;
  std::uint32_t* counts = counts_.data();
  for (const Splat& splat : std::span(splats_).subspan(size_, count)) {
    if (splat.x1 - splat.x0 == 1 && splat.y1 - splat.y0 == 1) {
      ++counts[grid.tileOf(splat.x0, splat.y0)];
      continue;
    }
    single_ = false;
    forEachTile(grid, splat, [&](std::uint32_t tile) { ++counts[tile]; });
  }
  size_ += count;
}

template <class Splat>
void ChunkSorter<Splat>::addPixels(std::size_t count) {
  std::uint32_t* counts = counts_.data();  // a local, so the compiler need not reload it after every store
  for (const std::uint32_t key : std::span(keys_).subspan(pixelCount_, count)) ++counts[key >> 16];
  pixelCount_ += count;
}

template <class Splat>
void ChunkSorter<Splat>::sort(ChunkBins& bins) {
  assert(size_ == 0 || pixelCount_ == 0);
  const TileGrid& grid = *grid_;
  const std::span<const Splat> splats(splats_.data(), size_);
  // Exclusive prefix sum; the counts become each tile's write cursor.
  const std::uint32_t tiles = grid.count();
  std::uint32_t* offsets = sized(bins.offsets, tiles + 1);
  std::uint32_t* cursor = counts_.data();
  std::uint32_t total = 0;
  for (std::uint32_t tile = 0; tile < tiles; ++tile) {
    offsets[tile] = total;
    total += cursor[tile];
    cursor[tile] = offsets[tile];
  }
  offsets[tiles] = total;
  const std::uint32_t dropped = cursor[tiles];  // the fast path's, into the tile after the last
  cursor[tiles] = total;

  // Scattered into memory that stays in this core's cache, then copied to the bins in one sequential sweep:
  // scattered writes straight to the bins would each wait for a line last touched a batch ago.
  if (single_) {
    bins.kind = BinKind::pixels;
    PixelSplat* sorted = sized(sortedPixels_, total + dropped);
    const std::uint32_t mask = grid.tileSize() - 1;
    const std::uint32_t* keys = keys_.data();
    const float* depths = depths_.data();
    const std::uint32_t* payloads = payloads_.data();
    for (std::size_t i = 0; i < pixelCount_; ++i)
      sorted[cursor[keys[i] >> 16]++] = PixelSplat{keys[i] & 0xffffu, depths[i], payloads[i]};
    for (const Splat& splat : splats) {
      const std::uint32_t pixel = ((splat.y0 & mask) << grid.shift) | (splat.x0 & mask);
      sorted[cursor[grid.tileOf(splat.x0, splat.y0)]++] = PixelSplat{pixel, splat.depth, splat.payload};
    }
    std::copy_n(sorted, total, sized(bins.pixels, total));
    return;
  }
  Splat* sorted = sized(sortedSplats_, total);
  for (const Splat& splat : splats)
    forEachTile(grid, splat, [&](std::uint32_t tile) { sorted[cursor[tile]++] = splat; });
  std::copy_n(sorted, total, sized(binsOf(bins, splats.data()), total));
}

template class ChunkSorter<SquareSplat>;
template class ChunkSorter<DiscSplat>;

}  // namespace pbs::points
