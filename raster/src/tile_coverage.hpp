// Coverage and depth of one triangle within one tile: exact integer edge functions evaluated on
// 8×8 blocks anchored at the triangle's box (trivial accept and reject per block), or row by row
// for a triangle of at most 8 rows and two blocks in the tile (the common small one), with an
// 8-lane kernel in GCC vector extensions that compiles to branch-free AVX2 in the clone picked at
// load time (simd_clones.hpp) and to SSE pairs in the baseline one. Inlined into the tile loop,
// which is cloned, so that a triangle of a few pixels pays no call and reloads no constants.
#pragma once

#include "pbs/raster/simd_clones.hpp"
#include "tile_buffer.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

namespace pbs::triangles {
namespace coverage {

// A triangle no wider or taller than this (in 1/256 pixel: 64 pixels) has every edge value the
// block loop meets, up to 8 pixels beside its box, below 2^30 in magnitude: int32 suffices.
constexpr std::int64_t kSmallExtent = std::int64_t(1) << 14;

// A block row is one vector of eight 32-bit lanes: one AVX2 register in the AVX2 clone, a pair of
// SSE registers in the baseline one.
constexpr int kLanes = kBlockSize;

template <class T>
struct LaneVector {
  typedef T type __attribute__((vector_size(sizeof(T) * kLanes)));
};
template <class T>
using Lanes = typename LaneVector<T>::type;
using FloatLanes = Lanes<float>;
using MaskLanes = Lanes<std::int32_t>;  // all ones where a lane is drawn
using IdLanes = Lanes<std::uint32_t>;

// Lane numbers within a block row. (Vectors are passed by reference throughout: by value they
// would change the calling convention between SSE and AVX builds.)
static_assert(kLanes == 8);
constexpr MaskLanes kLaneIndex = {0, 1, 2, 3, 4, 5, 6, 7};

// One block row: lanes set in `lanes` whose biased edge values are all ≥ 0 (unless the block is
// known inside) and whose depth, clamped to [0, 1], is less than the stored one take that depth
// and `id`.
template <class Edge, bool kTestEdges>
PBS_CLONE_INLINE void rasterizeLanes(float* depth, std::uint32_t* ids, const Lanes<Edge> (&edge)[3],
                                     const MaskLanes& lanes, const FloatLanes& unclamped, std::uint32_t id) {
  // z < 0 ? 0 : (z > 1 ? 1 : z), NaN and −0 kept, written as (minps, maxps) would compute it:
  // min(a, b) = a < b ? a : b, max(a, b) = a > b ? a : b, exactly, for every input.
  const FloatLanes one = FloatLanes{} + 1.0f, zero = FloatLanes{};
  const FloatLanes below = one < unclamped ? one : unclamped;
  const FloatLanes z = zero > below ? zero : below;
  MaskLanes pass = lanes;
  if constexpr (kTestEdges) pass &= __builtin_convertvector((edge[0] | edge[1] | edge[2]) >= 0, MaskLanes);
  FloatLanes storedDepth;
  IdLanes storedIds;
  std::memcpy(&storedDepth, depth, sizeof storedDepth);
  std::memcpy(&storedIds, ids, sizeof storedIds);
  pass &= z < storedDepth;
  storedDepth = pass ? z : storedDepth;
  storedIds = pass ? IdLanes{} + id : storedIds;
  std::memcpy(depth, &storedDepth, sizeof storedDepth);
  std::memcpy(ids, &storedIds, sizeof storedIds);
}

// Rows y … y + rows − 1 of a block whose lane 0 lies at column bx: `edge` holds the lanes' edge
// values on row y, `lanes` which lanes are pixels of the triangle's box.
template <class Edge, bool kTestEdges>
PBS_CLONE_INLINE void rasterizeBlockRows(TileBuffer& tile, const RasterTriangle& t, Lanes<Edge> (&edge)[3],
                                         const Edge (&stepY)[3], const MaskLanes& lanes, int bx, int y, int rows,
                                         std::uint32_t id) {
  // The depth (z0 + zy·dy) + zx·dx: the zx·dx term per lane, the z0 + zy·dy term of each of the
  // block's rows computed at once, lane r for row y + r.
  const FloatLanes zColumn = t.zx * __builtin_convertvector(kLaneIndex + (bx - t.minX), FloatLanes);
  const FloatLanes zRowLanes = t.z0 + t.zy * __builtin_convertvector(kLaneIndex + (y - t.minY), FloatLanes);
  float zRows[kLanes];
  std::memcpy(zRows, &zRowLanes, sizeof zRows);
  float* depth = tile.depth + (y - tile.y0) * kTileStride + (bx - tile.x0);
  std::uint32_t* ids = tile.ids + (y - tile.y0) * kTileStride + (bx - tile.x0);
  for (int row = 0; row < rows; ++row, depth += kTileStride, ids += kTileStride) {
    const FloatLanes z = zColumn + zRows[row];
    rasterizeLanes<Edge, kTestEdges>(depth, ids, edge, lanes, z, id);
    for (int k = 0; k < 3; ++k) edge[k] += stepY[k];
  }
}

// {0, s, 2s, …, 7s}: one multiply of 32-bit lanes in AVX2; 64-bit lanes (which neither SSE2 nor
// AVX2 multiplies) built from scalars.
template <class Edge>
PBS_CLONE_INLINE void laneSteps(Edge s1, Lanes<Edge>& steps) {
  if constexpr (sizeof(Edge) == sizeof(std::int32_t)) {
    steps = kLaneIndex * s1;
  } else {
    const Edge s2 = s1 + s1, s4 = s2 + s2;
    steps = Lanes<Edge>{0, s1, s2, s2 + s1, s4, s4 + s1, s4 + s2, s4 + s2 + s1};
  }
}

// Four lanes of T, for the three edges of a triangle at once (the fourth lane unused).
template <class T>
struct EdgeLaneVector {
  typedef T type __attribute__((vector_size(4 * sizeof(T))));
};

// The edge functions of a triangle on the pixel grid, from the centre of pixel (ax, y0). Edge k runs
// from vertex k to k + 1; with the positive area set up, the inside is where its function is
// positive. Samples exactly on it belong to the triangle for top-left edges only, so the others
// get a bias of −1 and every test becomes "≥ 0".
//
// The three edges are set up together, one lane each, in unsigned lanes of Edge's width: for the
// 32-bit grid of a small triangle that is, modulo 2^32, exactly the 64-bit value truncated to 32
// bits; for the 64-bit grid it is exact. The coefficients a and c are exact either way (snapped
// coordinates lie within ±2^29), so the top-left test is too.
template <class Edge>
struct EdgeGrid {
  Edge origin[3], stepX[3], stepY[3];
  Lanes<Edge> laneStep[3];  // {0, 1, …, 7} · stepX

  PBS_CLONE_INLINE EdgeGrid(const RasterTriangle& t, int ax, int y0) {
    using Word = std::make_unsigned_t<Edge>;
    using Words = typename EdgeLaneVector<Word>::type;
    using Signed = typename EdgeLaneVector<Edge>::type;
    const auto word = [&](std::int32_t coordinate) { return Word(Edge(coordinate)); };
    const Words x = {word(t.x[0]), word(t.x[1]), word(t.x[2]), 0};
    const Words y = {word(t.y[0]), word(t.y[1]), word(t.y[2]), 0};
    const Words xNext = {word(t.x[1]), word(t.x[2]), word(t.x[0]), 0};
    const Words yNext = {word(t.y[1]), word(t.y[2]), word(t.y[0]), 0};
    const Words a = y - yNext;  // coefficients of x
    const Words c = xNext - x;  // coefficients of y
    const Signed signedA = Signed(a), signedC = Signed(c);
    const Signed topLeft = (signedA > 0) | ((signedA == 0) & (signedC > 0));  // all ones where true
    const Word sx = Word(ax) * Word(kSubpixelScale) + Word(kSubpixelScale / 2);
    const Word sy = Word(y0) * Word(kSubpixelScale) + Word(kSubpixelScale / 2);
    // + ~topLeft: adds 0 on top-left edges and all ones, that is −1, on the others.
    const Words originWords = a * (sx - x) + c * (sy - y) + Words(~topLeft);
    const Words stepXWords = a * Word(kSubpixelScale), stepYWords = c * Word(kSubpixelScale);
    for (int k = 0; k < 3; ++k) {
      origin[k] = Edge(originWords[k]);
      stepX[k] = Edge(stepXWords[k]);
      stepY[k] = Edge(stepYWords[k]);
      laneSteps(stepX[k], laneStep[k]);
    }
  }
};

// Which lanes of the block row starting at column bx lie in columns x0 … x1.
PBS_CLONE_INLINE void columnLanes(int bx, int x0, int x1, MaskLanes& lanes) {
  const MaskLanes column = kLaneIndex + bx;
  lanes = (column >= x0) & (column <= x1);
}

// A small rectangle, at most kBlockSize rows of at most two blocks: walked row by row with
// everything set up once, as a triangle of a few pixels costs more to set up than to test. The
// edge and depth values are those of the block loop below, so the two paths agree bit for bit.
template <class Edge>
PBS_CLONE_INLINE void rasterizeSmallRect(TileBuffer& tile, const RasterTriangle& t, int x0, int y0, int x1, int y1,
                                         std::uint32_t id) {
  const int ax = x0 & ~(kLanes - 1);
  const EdgeGrid<Edge> grid(t, ax, y0);
  const bool twoBlocks = x1 - ax >= kBlockSize;
  Lanes<Edge> edge[3], nextEdge[3];  // the rows' edge values in the first block and the next
  for (int k = 0; k < 3; ++k) edge[k] = grid.laneStep[k] + grid.origin[k];
  if (twoBlocks)
    for (int k = 0; k < 3; ++k) nextEdge[k] = edge[k] + grid.stepX[k] * Edge(kBlockSize);
  MaskLanes lanes, nextLanes;
  columnLanes(ax, x0, x1, lanes);
  columnLanes(ax + kBlockSize, x0, x1, nextLanes);
  // The depth (z0 + zy·dy) + zx·dx as in the block loop: the zx·dx term per lane, the z0 + zy·dy
  // term of each row computed at once, lane r for row y0 + r.
  const FloatLanes zColumn = t.zx * __builtin_convertvector(kLaneIndex + (ax - t.minX), FloatLanes);
  const FloatLanes nextZColumn = t.zx * __builtin_convertvector(kLaneIndex + (ax + kBlockSize - t.minX), FloatLanes);
  const FloatLanes zRowLanes = t.z0 + t.zy * __builtin_convertvector(kLaneIndex + (y0 - t.minY), FloatLanes);
  float zRows[kLanes];
  std::memcpy(zRows, &zRowLanes, sizeof zRows);
  float* depth = tile.depth + (y0 - tile.y0) * kTileStride + (ax - tile.x0);
  std::uint32_t* ids = tile.ids + (y0 - tile.y0) * kTileStride + (ax - tile.x0);
  for (int row = 0; row <= y1 - y0; ++row, depth += kTileStride, ids += kTileStride) {
    rasterizeLanes<Edge, true>(depth, ids, edge, lanes, zColumn + zRows[row], id);
    if (twoBlocks) {
      rasterizeLanes<Edge, true>(depth + kBlockSize, ids + kBlockSize, nextEdge, nextLanes, nextZColumn + zRows[row],
                                 id);
      for (int k = 0; k < 3; ++k) nextEdge[k] += grid.stepY[k];
    }
    for (int k = 0; k < 3; ++k) edge[k] += grid.stepY[k];
  }
}

// A block of a wide triangle (64-bit edges) that some edge crosses, in 32-bit lanes where that is exact:
// an edge inside over the block's pixels passes them all and is left out (lanes of 0), and the others
// must stay within int32 over the block's 8 × 8 lanes and the row step past its last row. Those near
// an edge have small values, so most blocks qualify; false (nothing drawn) where one does not.
PBS_CLONE_INLINE bool rasterizeNarrowBlock(TileBuffer& tile, const RasterTriangle& t,
                                           const EdgeGrid<std::int64_t>& grid, const bool (&inside)[3],
                                           const MaskLanes& lanes, int ax, int y0, int bx, int by, int rows,
                                           std::uint32_t id) {
  constexpr std::int64_t kLimit = std::numeric_limits<std::int32_t>::max();
  Lanes<std::int32_t> edge[3];
  std::int32_t stepY[3];
  for (int k = 0; k < 3; ++k) {
    edge[k] = Lanes<std::int32_t>{};
    stepY[k] = 0;
    if (inside[k]) continue;
    const std::int64_t first = grid.origin[k] + grid.stepX[k] * (bx - ax) + grid.stepY[k] * (by - y0);
    const std::int64_t sx = grid.stepX[k], sy = grid.stepY[k];
    const std::int64_t reach = (first < 0 ? -first : first) + kBlockSize * ((sx < 0 ? -sx : sx) + (sy < 0 ? -sy : sy));
    if (reach > kLimit) return false;
    edge[k] = kLaneIndex * std::int32_t(sx) + std::int32_t(first);
    stepY[k] = std::int32_t(sy);
  }
  rasterizeBlockRows<std::int32_t, true>(tile, t, edge, stepY, lanes, bx, by, rows, id);
  return true;
}

// Pixels x0 … x1 × y0 … y1 (window coordinates) of the triangle within the tile, in blocks of
// 8×8 starting at multiples of 8 columns: the 32-byte loads and stores of successive triangles
// then meet the earlier ones exactly or not at all, never partly, which would defeat
// store-to-load forwarding.
template <class Edge>
PBS_CLONE_INLINE void rasterizeRect(TileBuffer& tile, const RasterTriangle& t, int x0, int y0, int x1, int y1,
                                    std::uint32_t id) {
  const int ax = x0 & ~(kLanes - 1);
  const EdgeGrid<Edge> grid(t, ax, y0);
  const auto& origin = grid.origin;
  const auto& stepX = grid.stepX;
  const auto& stepY = grid.stepY;
  for (int by = y0; by <= y1; by += kBlockSize) {
    const int rows = std::min(kBlockSize, y1 - by + 1);
    for (int bx = ax; bx <= x1; bx += kBlockSize) {
      const int rx0 = std::max(bx, x0), rx1 = std::min(bx + kBlockSize - 1, x1);
      // A box of one block is rarely inside or outside the triangle as a whole: skip the test.
      bool reject = false, accept = false;
      bool inside[3] = {false, false, false};  // edges whose values are ≥ 0 over the block's pixels
      if (x1 - ax >= kBlockSize || y1 - y0 >= kBlockSize) {
        accept = true;
        for (int k = 0; k < 3; ++k) {
          const Edge corner = origin[k] + stepX[k] * Edge(rx0 - ax) + stepY[k] * Edge(by - y0);
          const Edge spanX = stepX[k] * Edge(rx1 - rx0), spanY = stepY[k] * Edge(rows - 1);
          reject |= corner + std::max<Edge>(spanX, 0) + std::max<Edge>(spanY, 0) < 0;
          inside[k] = corner + std::min<Edge>(spanX, 0) + std::min<Edge>(spanY, 0) >= 0;
          accept &= inside[k];
        }
      }
      if (reject) continue;
      MaskLanes lanes;
      columnLanes(bx, x0, x1, lanes);
      if constexpr (sizeof(Edge) > sizeof(std::int32_t)) {
        if (!accept && rasterizeNarrowBlock(tile, t, grid, inside, lanes, ax, y0, bx, by, rows, id)) continue;
      }
      Lanes<Edge> edge[3];  // from the centre of pixel (bx, by)
      for (int k = 0; k < 3; ++k)
        edge[k] = grid.laneStep[k] + (origin[k] + stepX[k] * Edge(bx - ax) + stepY[k] * Edge(by - y0));
      if (accept)
        rasterizeBlockRows<Edge, false>(tile, t, edge, stepY, lanes, bx, by, rows, id);
      else
        rasterizeBlockRows<Edge, true>(tile, t, edge, stepY, lanes, bx, by, rows, id);
    }
  }
}

}  // namespace coverage

// Depth-tests the triangle's covered pixel centres in the tile (less: an equal depth keeps the
// earlier triangle) and records `id` where it wins.
PBS_CLONE_INLINE void rasterizeInTile(TileBuffer& tile, const RasterTriangle& t, std::uint32_t id) {
  using namespace coverage;
  const int x0 = std::max<int>(t.minX, tile.x0), x1 = std::min<int>(t.maxX, tile.x0 + tile.width - 1);
  const int y0 = std::max<int>(t.minY, tile.y0), y1 = std::min<int>(t.maxY, tile.y0 + tile.height - 1);
  if (x0 > x1 || y0 > y1) return;
  const CoordinateRange x = rangeOf(t.x[0], t.x[1], t.x[2]), y = rangeOf(t.y[0], t.y[1], t.y[2]);
  if (std::int64_t(x.max) - x.min <= kSmallExtent && std::int64_t(y.max) - y.min <= kSmallExtent) {
    if (y1 - y0 < kBlockSize && x1 - (x0 & ~(kLanes - 1)) < 2 * kBlockSize)
      rasterizeSmallRect<std::int32_t>(tile, t, x0, y0, x1, y1, id);
    else
      rasterizeRect<std::int32_t>(tile, t, x0, y0, x1, y1, id);
  } else {
    rasterizeRect<std::int64_t>(tile, t, x0, y0, x1, y1, id);
  }
}

}  // namespace pbs::triangles
