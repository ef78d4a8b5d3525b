// The per-tile pass of drawPoints: the nearest-wins depth test over one tile's splats in submission order,
// then the channel writes for the points that won a pixel.
#pragma once

#include "points_bins.hpp"
#include "points_sets.hpp"
#include "scalable_vectors.hpp"

#include <cstdint>
#include <span>

namespace pbs::points {

// One thread's copy of a tile (stride tileSize): depth alone for a depth-only framebuffer, else depth packed
// with the winning splat's payload (points_tile.cpp).
struct TileScratch {
  UninitializedVector<float> depth;
  UninitializedVector<std::uint64_t> packed;
};

// Draws the splats binned to `tile` by every chunk of the batch starting at ordinal `batchStart`. Only this
// call writes the tile's pixels, so tiles run in parallel without atomics.
void drawTile(Framebuffer& framebuffer, const TileGrid& grid, std::uint32_t tile, std::span<const ChunkBins> chunks,
              const PointSets& sets, std::uint64_t batchStart, TileScratch& scratch);

}  // namespace pbs::points
