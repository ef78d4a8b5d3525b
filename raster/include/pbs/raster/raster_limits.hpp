// The rasterizer's fixed sizes and limits in one place (after Mesa llvmpipe's lp_limits.h): what the
// command line checks a size against, and the constants the triangle and point rasterizers are built on.
#pragma once

#include <cstddef>
#include <cstdint>

namespace pbs {

// The largest viewport side, in pixels: edge functions stay exact in 64-bit integers up to it
// (kGuardBandPixels), and every command's --size is checked against it.
inline constexpr std::uint32_t kMaxViewportSize = 16384;

// Triangles: vertices snap to 1/2^kSubpixelBits of a pixel; the screen is cut into kTriangleTileSize²
// tiles (each one TBB task), tested kTriangleBlockSize² pixels at a time for trivial accept and reject.
inline constexpr int kSubpixelBits = 8;
inline constexpr int kTriangleTileSize = 64;
inline constexpr int kTriangleBlockSize = 8;

// Vertices farther than 2^21 pixels from the window origin are clipped in x/y (in homogeneous space,
// like near and far); everything within is rasterized unclipped. It keeps snapped coordinates within
// ±2^29 subpixels, so an edge coefficient is below 2^30 and an edge function at any pixel centre of a
// kMaxViewportSize² viewport sums two products below 2^60: exact in int64.
inline constexpr double kGuardBandPixels = double(1 << 21);
static_assert(kMaxViewportSize <= (1u << 14), "edge functions of larger viewports could overflow int64");

// Points: square tiles of 2^kPointTileShiftMin … 2^kPointTileShiftMax pixels (16–256), chosen per
// framebuffer so that it has kPointTilesMin … kPointTilesMax tiles.
inline constexpr int kPointTileShiftMin = 4;
inline constexpr int kPointTileShiftMax = 8;
inline constexpr std::uint32_t kPointTilesMin = 64;
inline constexpr std::uint32_t kPointTilesMax = 4096;

// What the triangle rasterizer's working memory takes per triangle of a batch, about (vertex cache, set-up
// triangles, bins: a frame of the default scene's approach at 1920×1080, 19 M triangles in batches of 2^18,
// uses up to 45 MB), and what a thread that draws triangles keeps of it from one draw call to the next at
// most: a full batch's.
inline constexpr std::size_t kTriangleBufferBytesPerTriangle = 256;
inline constexpr std::size_t kKeptTriangleBufferBytes = kTriangleBufferBytesPerTriangle << 18;

}  // namespace pbs
