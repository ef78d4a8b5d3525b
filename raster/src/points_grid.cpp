// The choice of tile size for a framebuffer.
#include "points_grid.hpp"

namespace pbs::points {

TileGrid makeTileGrid(std::uint32_t width, std::uint32_t height) {
  TileGrid grid;
  grid.width = width;
  grid.height = height;
  const auto tilesAt = [&](int shift) {
    const std::uint32_t size = 1u << shift;
    return ((width + size - 1) >> shift) * ((height + size - 1) >> shift);
  };
  while (grid.shift < kPointTileShiftMax && tilesAt(grid.shift) > kPointTilesMax) ++grid.shift;
  while (grid.shift > kPointTileShiftMin && tilesAt(grid.shift) < kPointTilesMin) --grid.shift;
  const std::uint32_t size = grid.tileSize();
  grid.columns = (width + size - 1) >> grid.shift;
  grid.rows = (height + size - 1) >> grid.shift;
  return grid;
}

}  // namespace pbs::points
