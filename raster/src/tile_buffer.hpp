// The pixels of one tile while a batch's triangles are rasterized into it: depth and the id of
// the triangle that won each pixel, whose attributes are resolved once at the end.
#pragma once

#include "shading_records.hpp"
#include "triangle_batch.hpp"

#include <cstdint>
#include <vector>

namespace pbs::triangles {

// Blocks start at multiples of kBlockSize columns, so they never reach past the tile's 64 columns;
// in a tile narrower than that (at the window's right edge) lanes past its edge are masked but
// still loaded and stored.
inline constexpr int kTileStride = kTileSize;
static_assert(kTileSize % kBlockSize == 0);

struct TileBuffer {
  int x0 = 0, y0 = 0;         // window pixel of the tile's first pixel
  int width = 0, height = 0;  // ≤ kTileSize; smaller at the right and bottom of the window
  alignas(64) float depth[kTileSize * kTileStride];
  alignas(64) std::uint32_t ids[kTileSize * kTileStride];  // places in TileDrawn; kNoTriangle where none won
};

// Whether the triangle's pixel box meets the tile.
inline bool overlaps(const RasterTriangle& t, const TileBuffer& tile) {
  return t.maxX >= tile.x0 && t.minX < tile.x0 + tile.width && t.maxY >= tile.y0 && t.minY < tile.y0 + tile.height;
}

// The triangles a tile drew, in the order it drew them: a pixel's id in TileBuffer::ids is a place
// here. The resolve's working memory beside them: per place the slot of its shading record where it
// won a pixel, those winners in the order drawn with where their records come from, and the records (at
// most one per pixel).
struct TileDrawn {
  std::vector<const RasterTriangle*> triangles;
  std::vector<std::uint32_t> slotOf;
  std::vector<const RasterTriangle*> winners;
  std::vector<TriangleSource> sources;  // the winners', found once
  std::vector<float> records;
  std::vector<float> textureLevels;  // per record of an affine textured triangle: its one probe's level of detail
};

// Writes the channels other than depth for every pixel a triangle of this batch won.
void resolveTile(const TriangleBatch& batch, const TileBuffer& tile, TileDrawn& drawn);

}  // namespace pbs::triangles
