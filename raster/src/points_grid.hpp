// The screen tiles of the point rasterizer: each is drawn by one task, which owns its pixels.
#pragma once

#include "pbs/raster/raster_limits.hpp"

#include <cstdint>

namespace pbs::points {

// The largest tile side makeTileGrid chooses.
inline constexpr int kMaxTileShift = kPointTileShiftMax;
inline constexpr std::uint32_t kMaxTileSize = 1u << kMaxTileShift;

// Square tiles of 2^shift pixels covering the framebuffer, numbered row-major.
struct TileGrid {
  std::uint32_t width = 0;  // framebuffer
  std::uint32_t height = 0;
  int shift = 6;
  std::uint32_t columns = 0;
  std::uint32_t rows = 0;

  std::uint32_t tileSize() const { return 1u << shift; }
  std::uint32_t count() const { return columns * rows; }
  std::uint32_t tileOf(std::uint32_t x, std::uint32_t y) const { return (y >> shift) * columns + (x >> shift); }
};

// Tiles small enough to keep a tile's depth in L1 and to give every thread work, few enough that the
// per-chunk counts stay cheap. Depends only on the framebuffer size, never on the thread count.
TileGrid makeTileGrid(std::uint32_t width, std::uint32_t height);

}  // namespace pbs::points
