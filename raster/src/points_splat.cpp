// Block-wise projection of points to square and disc splats (see points_splat.hpp).
#include "points_splat.hpp"
#include "pbs/raster/simd_clones.hpp"

namespace pbs::points {

namespace {

// The block loops are also compiled for AVX2 and AVX-512 (simd_clones.hpp): the portable x86-64 build has only
// SSE2, for which GCC does not vectorise the double ↔ int conversions; AVX-512's wider vectors and 32 registers
// (the block loops spill with 16) take about 6 % off a 1-pixel draw where the CPU has them.
#define PBS_BLOCK_CLONES PBS_AVX512_CLONES

// ceil and floor of a double well inside the int range, written so the block loops vectorise (baseline
// x86-64 has no rounding instruction and a libm call per point would dominate).
inline int ceilToInt(double v) {
  const int t = static_cast<int>(v);
  return t + (static_cast<double>(t) < v);
}
inline int floorToInt(double v) {
  const int t = static_cast<int>(v);
  return t - (static_cast<double>(t) > v);
}

// Window positions are clamped to this far outside the viewport, where no splat (half of 4096 at most) reaches
// it; dropped points are put there too. This keeps every integer conversion in range.
constexpr double kReach = 4100.0;

// Window coordinates of one block, structure of arrays; a dropped point sits at x = −kReach, off the viewport.
struct Window {
  alignas(64) double x[kBlockPoints];
  alignas(64) double y[kBlockPoints];
  alignas(64) double half[kBlockPoints];  // half the drawn size
  alignas(64) float depth[kBlockPoints];
};

// One point's window position, clamped to kReach around the viewport, its depth, and whether it may draw.
struct WindowPoint {
  double x, y;
  float depth;
  bool keep;
};

// Where the matrix's w row is (0, 0, 0, 1) (orthographic), w is exactly 1 for a finite position, so kAffine
// skips w and the division, the slowest step of the loop. A position that is not finite is dropped all the same:
// each of x, y and z sums a multiple of every coordinate, so z is NaN or infinite and fails the depth test.
template <bool kAffine>
PBS_CLONE_INLINE WindowPoint windowPoint(const glm::dmat4& m, const glm::vec3& position, float size, double xHigh,
                                         double yHigh) {
  const double low = -kReach;
  const double px = position.x, py = position.y, pz = position.z;
  double wx = m[0][0] * px + m[1][0] * py + m[2][0] * pz + m[3][0];
  double wy = m[0][1] * px + m[1][1] * py + m[2][1] * pz + m[3][1];
  double depth = m[0][2] * px + m[1][2] * py + m[2][2] * pz + m[3][2];
  bool front = true;
  if constexpr (!kAffine) {
    const double w = m[0][3] * px + m[1][3] * py + m[2][3] * pz + m[3][3];
    const double inverse = 1.0 / w;
    wx *= inverse;
    wy *= inverse;
    depth *= inverse;
    front = w > 0.0;
  }
  // Comparisons that fail for NaN, so NaN and infinite positions are dropped too.
  const bool keep = front & (depth >= 0.0) & (depth <= 1.0) & (size > 0.0f);
  // Clamped so that NaN becomes low (std::max(low, NaN) is low), written as min and max for GCC to vectorise.
  const double cx = std::min(xHigh, std::max(low, wx));
  const double cy = std::min(yHigh, std::max(low, wy));
  return {cx, cy, static_cast<float>(depth), keep};
}

template <bool kAffine>
PBS_CLONE_INLINE void windowBlockWith(const glm::dmat4& windowFromObject, const glm::vec3* __restrict positions,
                                      const float* __restrict sizes, std::size_t n, int width, int height,
                                      Window& __restrict window) {
  const glm::dmat4 m = windowFromObject;
  const double xHigh = width + kReach, yHigh = height + kReach;
  for (std::size_t i = 0; i < n; ++i) {
    const WindowPoint point = windowPoint<kAffine>(m, positions[i], sizes[i], xHigh, yHigh);
    window.x[i] = point.keep ? point.x : -kReach;
    window.y[i] = point.y;
    window.half[i] = static_cast<double>(sizes[i]) * 0.5;
    window.depth[i] = point.depth;
  }
}

PBS_BLOCK_CLONES
void windowBlockAffine(const glm::dmat4& windowFromObject, const glm::vec3* __restrict positions,
                       const float* __restrict sizes, std::size_t n, int width, int height, Window& __restrict window) {
  windowBlockWith<true>(windowFromObject, positions, sizes, n, width, height, window);
}

PBS_BLOCK_CLONES
void windowBlockProjective(const glm::dmat4& windowFromObject, const glm::vec3* __restrict positions,
                           const float* __restrict sizes, std::size_t n, int width, int height,
                           Window& __restrict window) {
  windowBlockWith<false>(windowFromObject, positions, sizes, n, width, height, window);
}

// `affine`: windowFromObject keeps w ≡ 1, so windowPoint<true> applies.
void windowBlock(const glm::dmat4& windowFromObject, bool affine, const glm::vec3* positions, const float* sizes,
                 std::size_t n, int width, int height, Window& window) {
  if (affine)
    windowBlockAffine(windowFromObject, positions, sizes, n, width, height, window);
  else
    windowBlockProjective(windowFromObject, positions, sizes, n, width, height, window);
}

// Pixel rectangles [x0, x1) × [y0, y1) of one block, clipped to the viewport; empty for a dropped point.
struct Rects {
  alignas(64) int x0[kBlockPoints];
  alignas(64) int x1[kBlockPoints];
  alignas(64) int y0[kBlockPoints];
  alignas(64) int y1[kBlockPoints];
};

// A square's pixels along one axis: centres c = p + 0.5 with x − s/2 ≤ c < x + s/2, clipped to [0, n) as
// [lo, hi). "− 0.5" is exact wherever the result matters.
inline void squareAxis(double c, double half, int n, int& lo, int& hi) {
  lo = std::max(ceilToInt((c - half) - 0.5), 0);
  hi = std::min(ceilToInt((c + half) - 0.5), n);
}

PBS_BLOCK_CLONES
void squareRects(const Window& __restrict window, std::size_t n, int width, int height, Rects& __restrict rects) {
  for (std::size_t i = 0; i < n; ++i) {
    squareAxis(window.x[i], window.half[i], width, rects.x0[i], rects.x1[i]);
    squareAxis(window.y[i], window.half[i], height, rects.y0[i], rects.y1[i]);
  }
}

// PixelKeys' key of pixel (x, y), or of the tile past the last when `inside` is false.
PBS_CLONE_INLINE std::uint32_t pixelKey(const TileGrid& grid, int x, int y, bool inside) {
  const int mask = int(grid.tileSize()) - 1;
  const int tile = (y >> grid.shift) * int(grid.columns) + (x >> grid.shift);
  return static_cast<std::uint32_t>(inside ? tile << 16 | (y & mask) << grid.shift | (x & mask)
                                           : int(grid.count()) << 16);
}

// The key of a 1-pixel square at window position (x, y). With s = 1 the clipped span has one pixel or none;
// the arithmetic is squareAxis's, so the paths agree.
PBS_CLONE_INLINE std::uint32_t squarePixel(const TileGrid& grid, const WindowPoint& point) {
  int x0, x1, y0, y1;
  squareAxis(point.x, 0.5, int(grid.width), x0, x1);
  squareAxis(point.y, 0.5, int(grid.height), y0, y1);
  return pixelKey(grid, x0, y0, point.keep & (x0 < x1) & (y0 < y1));
}

// The key of a 1-pixel disc: no pixel centre is strictly within ½ of (x, y) but the holding pixel's, so it
// covers just that.
PBS_CLONE_INLINE std::uint32_t discPixel(const TileGrid& grid, const WindowPoint& point) {
  const int x = floorToInt(point.x), y = floorToInt(point.y);
  return pixelKey(grid, x, y, point.keep & (x >= 0) & (x < int(grid.width)) & (y >= 0) & (y < int(grid.height)));
}

// Window position and pixel in one pass, the block never leaving registers. A dropped point's key says so
// directly (the keep flag is not folded into x as for Window: GCC then fails to vectorise the loop). The grid is
// a copy: the stored keys could otherwise alias its fields, which would stop vectorisation.
template <bool kAffine, bool kRound>
PBS_CLONE_INLINE void pixelLoop(const glm::dmat4& windowFromObject, const glm::vec3* __restrict positions,
                                const float* __restrict sizes, std::size_t n, const TileGrid grid,
                                std::uint32_t* __restrict key, float* __restrict depth) {
  const glm::dmat4 m = windowFromObject;
  const double xHigh = grid.width + kReach, yHigh = grid.height + kReach;
  for (std::size_t i = 0; i < n; ++i) {
    const WindowPoint point = windowPoint<kAffine>(m, positions[i], sizes[i], xHigh, yHigh);
    key[i] = kRound ? discPixel(grid, point) : squarePixel(grid, point);
    depth[i] = point.depth;
  }
}

template <bool kAffine>
PBS_CLONE_INLINE void pixelBlockWith(const glm::dmat4& windowFromObject, const glm::vec3* __restrict positions,
                                     const float* __restrict sizes, std::size_t n, const TileGrid& grid, bool round,
                                     std::uint32_t* __restrict key, float* __restrict depth) {
  if (round)
    pixelLoop<kAffine, true>(windowFromObject, positions, sizes, n, grid, key, depth);
  else
    pixelLoop<kAffine, false>(windowFromObject, positions, sizes, n, grid, key, depth);
}

PBS_BLOCK_CLONES
void pixelBlockAffine(const glm::dmat4& windowFromObject, const glm::vec3* __restrict positions,
                      const float* __restrict sizes, std::size_t n, const TileGrid& grid, bool round,
                      std::uint32_t* __restrict key, float* __restrict depth) {
  pixelBlockWith<true>(windowFromObject, positions, sizes, n, grid, round, key, depth);
}

PBS_BLOCK_CLONES
void pixelBlockProjective(const glm::dmat4& windowFromObject, const glm::vec3* __restrict positions,
                          const float* __restrict sizes, std::size_t n, const TileGrid& grid, bool round,
                          std::uint32_t* __restrict key, float* __restrict depth) {
  pixelBlockWith<false>(windowFromObject, positions, sizes, n, grid, round, key, depth);
}

// Along one axis: the pixels whose centre lies strictly within `radius` of c, with the one holding c when
// `withHolding`, clipped to [0, n). The real-number answer is corrected by one step either way with the same
// floating-point test as the per-pixel coverage: rounding moves the edge by ulps, so by one pixel at most.
inline void discAxis(double c, double radius, int n, bool withHolding, int& lo, int& hi) {
  const double radiusSquared = radius * radius;
  const auto within = [&](int p) {
    const double d = (p + 0.5) - c;
    return d * d < radiusSquared;
  };
  int first = floorToInt(c - radius - 0.5) + 1;
  int last = ceilToInt(c + radius - 0.5) - 1;
  first -= within(first - 1);
  last += within(last + 1);
  first += !within(first);
  last -= !within(last);
  // A non-empty span contains the holding pixel (whose centre is the nearest), so the union is a span.
  if (!withHolding) {
    lo = std::max(first, 0);
    hi = std::min(last + 1, n);
    return;
  }
  const int hold = floorToInt(c);
  const bool empty = first > last;
  lo = std::max(std::min(empty ? hold : first, hold), 0);
  hi = std::min(std::max(empty ? hold : last, hold) + 1, n);
}

// The bounding rectangles of discs: every covered pixel lies inside, not every pixel inside is covered.
PBS_BLOCK_CLONES
void discRects(const Window& __restrict window, std::size_t n, int width, int height, bool withHolding,
               Rects& __restrict rects) {
  for (std::size_t i = 0; i < n; ++i) {
    discAxis(window.x[i], window.half[i], width, withHolding, rects.x0[i], rects.x1[i]);
    discAxis(window.y[i], window.half[i], height, withHolding, rects.y0[i], rects.y1[i]);
  }
}

void setRect(SquareSplat& splat, const Rects& rects, std::size_t i, float depth, std::uint32_t payload) {
  splat.x0 = static_cast<std::uint16_t>(rects.x0[i]);
  splat.y0 = static_cast<std::uint16_t>(rects.y0[i]);
  splat.x1 = static_cast<std::uint16_t>(rects.x1[i]);
  splat.y1 = static_cast<std::uint16_t>(rects.y1[i]);
  splat.depth = depth;
  splat.payload = payload;
}

}  // namespace

SplatProjector::SplatProjector(const Camera& camera, const glm::dmat4& clipFromObject, bool subPixel)
    : width_(static_cast<int>(camera.width)), height_(static_cast<int>(camera.height)), subPixel_(subPixel) {
  windowFromObject_ = windowFromClipMatrix(camera) * clipFromObject;
  affine_ = keepsUnitW(windowFromObject_);
}

std::size_t SplatProjector::project(std::span<const glm::vec3> positions, const float* sizes,
                                    const std::uint32_t* payloads, SquareSplat* out) const {
  Window window;
  windowBlock(windowFromObject_, affine_, positions.data(), sizes, positions.size(), width_, height_, window);
  Rects rects;
  squareRects(window, positions.size(), width_, height_, rects);
  std::size_t count = 0;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (rects.x0[i] >= rects.x1[i] || rects.y0[i] >= rects.y1[i]) continue;
    setRect(out[count++], rects, i, window.depth[i], payloads[i]);
  }
  return count;
}

std::size_t SplatProjector::project(std::span<const glm::vec3> positions, const float* sizes,
                                    const std::uint32_t* payloads, DiscSplat* out) const {
  Window window;
  windowBlock(windowFromObject_, affine_, positions.data(), sizes, positions.size(), width_, height_, window);
  Rects rects;
  discRects(window, positions.size(), width_, height_, !subPixel_, rects);
  std::size_t count = 0;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (rects.x0[i] >= rects.x1[i] || rects.y0[i] >= rects.y1[i]) continue;
    DiscSplat& splat = out[count];
    splat.x = window.x[i];
    splat.y = window.y[i];
    splat.radiusSquared = window.half[i] * window.half[i];
    splat.holdX = subPixel_ ? -1 : floorToInt(splat.x);
    splat.holdY = subPixel_ ? -1 : floorToInt(splat.y);
    // Splats of one pixel skip the per-pixel test later (the 1-pixel fast path), so test it here: clipping can
    // leave a single pixel of the bounding box that the disc misses.
    const bool onePixel = rects.x1[i] - rects.x0[i] == 1 && rects.y1[i] - rects.y0[i] == 1;
    if (onePixel && !splat.covers(rects.x0[i], rects.y0[i])) continue;
    setRect(splat, rects, i, window.depth[i], payloads[i]);
    ++count;
  }
  return count;
}

void SplatProjector::projectPixels(std::span<const glm::vec3> positions, const float* sizes, bool round,
                                   const TileGrid& grid, PixelKeys pixels) const {
  if (affine_)
    pixelBlockAffine(windowFromObject_, positions.data(), sizes, positions.size(), grid, round, pixels.key,
                     pixels.depth);
  else
    pixelBlockProjective(windowFromObject_, positions.data(), sizes, positions.size(), grid, round, pixels.key,
                         pixels.depth);
}

}  // namespace pbs::points
