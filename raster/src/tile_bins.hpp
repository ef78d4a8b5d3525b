// Which bins a set-up triangle goes to: the tiles its pixel box touches, or the large-triangle bin.
#pragma once

#include "triangle_batch.hpp"

namespace pbs::triangles {

// Calls visit(bin, unit) for every bin of the triangle: its tiles in row order, or the large-triangle
// bin (the one past the last tile) when it spans more than kMaxBinnedTiles tiles; unit is kSoleUnit
// where the triangle lies in that one tile alone (copied into the bin), else kSharedUnit (its id).
template <class Visit>
[[gnu::always_inline]] inline void forEachBin(const TriangleBatch& batch, const RasterTriangle& t, Visit visit) {
  const int x0 = t.minX / kTileSize, x1 = t.maxX / kTileSize;
  const int y0 = t.minY / kTileSize, y1 = t.maxY / kTileSize;
  // Most triangles lie within one tile: no loops for them.
  if (x0 == x1 && y0 == y1) {
    visit(y0 * batch.tilesX + x0, kSoleUnit);
    return;
  }
  if ((x1 - x0 + 1) * (y1 - y0 + 1) > kMaxBinnedTiles) {
    visit(batch.tileCount(), kSharedUnit);
    return;
  }
  for (int ty = y0; ty <= y1; ++ty)
    for (int tx = x0; tx <= x1; ++tx) visit(ty * batch.tilesX + tx, kSharedUnit);
}

inline std::size_t binCount(const TriangleBatch& batch) { return std::size_t(batch.tileCount()) + 1; }

}  // namespace pbs::triangles
