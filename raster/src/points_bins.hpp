// Binning of projected splats to screen tiles: a stable counting sort per chunk of points, so that each tile
// reads its splats in submission order, chunk after chunk, without a global sort or any shared counter.
#pragma once

#include "points_grid.hpp"
#include "points_splat.hpp"
#include "scalable_vectors.hpp"

#include <cstdint>
#include <span>

namespace pbs::points {

// A splat covering exactly one pixel, by its index inside the tile (row-major, stride tileSize).
struct PixelSplat {
  std::uint32_t pixel;
  float depth;
  std::uint32_t payload;
};

enum class BinKind { pixels, squares, discs };

// One chunk's splats sorted by tile: tile t's are [offsets[t], offsets[t + 1]) of the vector `kind` names.
// A chunk whose splats all cover one pixel stores the compact PixelSplat: the 1-pixel fast path.
struct ChunkBins {
  BinKind kind = BinKind::pixels;
  UninitializedVector<std::uint32_t> offsets;
  UninitializedVector<PixelSplat> pixels;
  UninitializedVector<SquareSplat> squares;
  UninitializedVector<DiscSplat> discs;

  // Calls f with the span of this chunk's splats binned to `tile`, of the type `kind` names.
  template <class F>
  void visit(std::uint32_t tile, F&& f) const {
    const std::uint32_t begin = offsets[tile], count = offsets[tile + 1] - begin;
    switch (kind) {
      case BinKind::pixels: return f(std::span(pixels).subspan(begin, count));
      case BinKind::squares: return f(std::span(squares).subspan(begin, count));
      case BinKind::discs: return f(std::span(discs).subspan(begin, count));
    }
  }
};

// Sorts one chunk's splats by tile: the projector writes them block by block at next(), add() counts their
// tiles while they are still in L1, and sort() moves them into the chunk's bins. A chunk whose points all
// have drawn size 1 takes the fast path instead: the projector writes their keys, depths and payloads as
// columns at pixels() and addPixels() counts their tiles. A chunk uses one or the other, so its splats stay in
// submission order. Reused from chunk to chunk, its memory only grows.
template <class Splat>
class ChunkSorter {
 public:
  // The fast path's columns for the chunk's next points: PixelKeys' key and depth, and the payloads.
  struct PixelColumns {
    PixelKeys keys;
    std::uint32_t* payloads;
  };

  // Starts a chunk of at most `points` points.
  void start(const TileGrid& grid, std::size_t points);
  Splat* next() { return splats_.data() + size_; }
  void add(std::size_t count);
  PixelColumns pixels() {
    return {{keys_.data() + pixelCount_, depths_.data() + pixelCount_}, payloads_.data() + pixelCount_};
  }
  void addPixels(std::size_t count);
  void sort(ChunkBins& bins);

 private:
  const TileGrid* grid_ = nullptr;
  UninitializedVector<Splat> splats_;
  // The fast path's columns, in submission order.
  UninitializedVector<std::uint32_t> keys_;
  UninitializedVector<float> depths_;
  UninitializedVector<std::uint32_t> payloads_;
  UninitializedVector<PixelSplat> sortedPixels_;
  UninitializedVector<Splat> sortedSplats_;
  ScalableVector<std::uint32_t> counts_;  // per tile, and for the fast path's dropped points past the last
  std::size_t size_ = 0;
  std::size_t pixelCount_ = 0;
  bool single_ = true;  // every splat from add() so far covers one pixel
};

extern template class ChunkSorter<SquareSplat>;
extern template class ChunkSorter<DiscSplat>;

}  // namespace pbs::points
