// Projection of points to splats: the pixels each may cover, its depth and, for discs, the exact centre.
#pragma once

#include "pbs/raster/camera.hpp"

#include "points_grid.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>

namespace pbs::points {

inline constexpr float kMaxPointSize = 4096.0f;

// Points are projected in blocks of this many: small enough for the block's window coordinates to stay in L1.
inline constexpr std::size_t kBlockPoints = 256;

// The drawn size of a point of nominal size pointSize × factor (points.hpp); 0 when it draws nothing.
// `smallest`: 1 (GL's minimum point size) or 0 (PointOptions::subPixel).
inline float splatSize(float size, float smallest) {
  const float clamped = std::min(std::max(size, smallest), kMaxPointSize);
  return size > 0.0f && size <= std::numeric_limits<float>::max() ? clamped : 0.0f;
}

// The pixels [x0, x1) × [y0, y1) a splat may cover (inside the viewport), its depth and its payload: what the
// point writes besides depth (PointSets::payloads). For a square these are exactly the covered pixels.
struct SquareSplat {
  std::uint16_t x0, y0, x1, y1;
  float depth;
  std::uint32_t payload;
};

// A disc's rectangle bounds its pixels; each is tested against the centre, as points.hpp defines it.
struct DiscSplat : SquareSplat {
  double x, y;           // window position of the centre
  double radiusSquared;  // (size / 2)²
  int holdX, holdY;      // the pixel holding the centre, always covered; −1 for sub-pixel discs (none)

  bool covers(int px, int py) const {
    const double dx = (px + 0.5) - x;
    const double dy = (py + 0.5) - y;
    return dx * dx + dy * dy < radiusSquared || (px == holdX && py == holdY);
  }
};

// Where the 1-pixel fast path writes a block's points: for each the pixel it covers when its drawn size is 1,
// as both shapes then cover exactly one (the square the pixel whose centre lies in [x − ½, x + ½) × [y − ½,
// y + ½), the disc the pixel holding (x, y)), and its depth. The key is tile << 16 | pixel in the tile (tiles
// number at most 4096 and hold at most 2^16 pixels, see makeTileGrid); a point that draws nothing keys tile
// grid.count(), one past the last, so that sorting by tile drops it without a test.
struct PixelKeys {
  std::uint32_t* key;
  float* depth;
};

// Projects the points of one set. camera.hpp's viewport mapping is folded into the matrix, so a point costs one
// division and the loops vectorise. w is exactly clip w; x, y and depth agree with windowFromClip to rounding
// (around 1e-12 pixel), and exactly wherever the arithmetic is exact.
class SplatProjector {
 public:
  // `subPixel`: discs cover only the pixels whose centres they contain, not also the one holding them.
  SplatProjector(const Camera& camera, const glm::dmat4& clipFromObject, bool subPixel);

  // Projects positions (at most kBlockPoints) with their drawn sizes (from splatSize) and payloads, and writes
  // the splats of those that cover a pixel to `out`; returns how many it wrote. A point is dropped outside
  // near/far, with w ≤ 0, with size 0, or off the viewport.
  std::size_t project(std::span<const glm::vec3> positions, const float* sizes, const std::uint32_t* payloads,
                      SquareSplat* out) const;
  std::size_t project(std::span<const glm::vec3> positions, const float* sizes, const std::uint32_t* payloads,
                      DiscSplat* out) const;

  // The 1-pixel fast path, for points whose drawn size is 1 or 0; the same pixels as project() for them.
  void projectPixels(std::span<const glm::vec3> positions, const float* sizes, bool round, const TileGrid& grid,
                     PixelKeys pixels) const;

 private:
  glm::dmat4 windowFromObject_;
  bool affine_;  // w ≡ 1 (keepsUnitW): the division by w is skipped
  int width_;
  int height_;
  bool subPixel_;
};

}  // namespace pbs::points
