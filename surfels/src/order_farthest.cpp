// orderFarthest: the exact greedy permutation with per-point distances, a cell grid (in blocks, to skip empty
// space) and a lazy heap of cells.
#include "order_nearest_grid.hpp"

#include <pbs/raster/simd_clones.hpp>
#include <pbs/surfels/ordering.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>

namespace pbs {

namespace {

// The input sorted cell by cell into a uniform grid once, so a radius query reads contiguous memory.
struct CellSortedPoints {
  glm::vec3 lo{0.0f};
  float cellSize = 1.0f;
  glm::ivec3 dims{1};
  std::vector<std::uint32_t> cellStart;  // per cell, first slot; one extra entry at the end
  // Per slot, the position as three arrays, so a cell's distances update in vector lanes.
  std::vector<float> x, y, z;
  std::vector<std::uint32_t> index;   // per slot: the input index, increasing within a cell
  std::vector<std::uint32_t> slotOf;  // per input index: its slot
  // Blocks of kBlock³ cells, and whether each holds a point: a surface leaves most cells of a 3D grid
  // empty, and the early, wide searches would otherwise visit them one by one.
  glm::ivec3 blockDims{1};
  std::vector<std::uint8_t> blockOccupied;
  // Cell and block boxes are widened by this much when distances to them are taken: a box's corners are
  // computed, not stored, and float rounding may leave a point of the cell a few units in the last
  // place outside them.
  float slack = 0.0f;

  glm::ivec3 cellOf(const glm::vec3& p) const {
    return glm::clamp(glm::ivec3(glm::floor((p - lo) / cellSize)), glm::ivec3(0), dims - 1);
  }
  std::size_t linear(const glm::ivec3& c) const {
    return (static_cast<std::size_t>(c.z) * dims.y + c.y) * dims.x + c.x;
  }
  std::size_t blockLinear(const glm::ivec3& b) const {
    return (static_cast<std::size_t>(b.z) * blockDims.y + b.y) * blockDims.x + b.x;
  }
};

constexpr int kBlockShift = 2;  // blocks of 4 × 4 × 4 cells

glm::ivec3 dimsFor(const glm::vec3& extent, float cellSize) { return glm::ivec3(glm::floor(extent / cellSize)) + 1; }

// Cells about 1.6 times the spacing of the last chosen points (extent / sqrt(max) on a surface), but no
// more cells than twice the points, so memory and empty-cell visits stay linear. Larger cells rescan more
// points per choice in vector lanes but visit fewer cells and keep a smaller heap: at 1.6 pbs surfelize
// default took 0.93x the time of 1.0 (four alternated pairs), 0.6 took 1.15x, 2.2 and 3.0 no less than 1.6.
CellSortedPoints sortIntoCells(std::span<const glm::vec3> points, std::uint32_t max) {
  CellSortedPoints grid;
  // Finite, at most 1e18 wide, and 0 wide below float's smallest normal (so cellSize never becomes 0).
  const OrderableBox box = orderableBox(points, "orderFarthest");
  grid.lo = box.lo;
  const glm::vec3 extent = box.extent;
  const float maxExtent = std::max({extent.x, extent.y, extent.z});
  if (maxExtent > 0.0f) {
    grid.cellSize = 1.6f * maxExtent / std::sqrt(static_cast<float>(std::max(1u, max)));
    const double cellLimit = 2.0 * static_cast<double>(points.size()) + 8.0;
    for (;;) {
      const glm::dvec3 d(dimsFor(extent, grid.cellSize));
      if (d.x * d.y * d.z <= cellLimit) break;
      grid.cellSize *= 1.25f;
    }
  }
  grid.dims = dimsFor(extent, grid.cellSize);
  const float magnitude =
      std::max({std::abs(box.lo.x), std::abs(box.lo.y), std::abs(box.lo.z), std::abs(box.lo.x + extent.x),
                std::abs(box.lo.y + extent.y), std::abs(box.lo.z + extent.z)});
  grid.slack = 1e-3f * grid.cellSize + 16.0f * std::numeric_limits<float>::epsilon() * magnitude;
  const std::size_t cells = static_cast<std::size_t>(grid.dims.x) * grid.dims.y * grid.dims.z;
  std::vector<std::uint32_t> cellOfPoint(points.size());
  grid.cellStart.assign(cells + 1, 0);
  grid.blockDims = ((grid.dims - 1) >> kBlockShift) + 1;
  grid.blockOccupied.assign(static_cast<std::size_t>(grid.blockDims.x) * grid.blockDims.y * grid.blockDims.z, 0);
  {
    // grid.cellOf for points of the box, where p - lo is not negative, so truncation is the floor (floor
    // itself is a long sequence on baseline x86-64). The grid's fields are copied: the byte stores
    // below may alias anything, and would have them reloaded per point.
    const glm::vec3 lo = grid.lo;
    const float cellSize = grid.cellSize;
    const glm::ivec3 dims = grid.dims, blockDims = grid.blockDims;
    std::uint32_t* count = grid.cellStart.data() + 1;
    std::uint8_t* blockOccupied = grid.blockOccupied.data();
    for (std::size_t i = 0; i < points.size(); ++i) {
      const glm::vec3 q = (points[i] - lo) / cellSize;
      const glm::ivec3 cell(std::min(int(q.x), dims.x - 1), std::min(int(q.y), dims.y - 1),
                            std::min(int(q.z), dims.z - 1));
      const glm::uvec3 u(cell);  // the cell's index modulo 2^32, as the static_cast of grid.linear gives
      const std::uint32_t c = (u.z * std::uint32_t(dims.y) + u.y) * std::uint32_t(dims.x) + u.x;
      cellOfPoint[i] = c;
      ++count[c];
      const glm::ivec3 block = cell >> kBlockShift;
      blockOccupied[(std::size_t(block.z) * blockDims.y + block.y) * blockDims.x + block.x] = 1;
    }
  }
  for (std::size_t c = 0; c < cells; ++c) grid.cellStart[c + 1] += grid.cellStart[c];
  std::vector<std::uint32_t> fill(grid.cellStart.begin(), grid.cellStart.end() - 1);
  grid.x.resize(points.size());
  grid.y.resize(points.size());
  grid.z.resize(points.size());
  grid.index.resize(points.size());
  grid.slotOf.resize(points.size());
  for (std::uint32_t i = 0; i < points.size(); ++i) {
    const std::uint32_t slot = fill[cellOfPoint[i]]++;
    grid.x[slot] = points[i].x;
    grid.y[slot] = points[i].y;
    grid.z[slot] = points[i].z;
    grid.index[slot] = i;
    grid.slotOf[i] = slot;
  }
  return grid;
}

// A heap key: the squared distance's bits (monotone for non-negative floats) above the complemented
// index, so the largest key is the farthest point and, among equals, the lowest index.
std::uint64_t heapKey(float squaredDistance, std::uint32_t index) {
  return (static_cast<std::uint64_t>(std::bit_cast<std::uint32_t>(squaredDistance)) << 32) | ~index;
}

// The squared distance a heap key holds (0 for a cell without pool points).
float keyDistance(std::uint64_t key) { return std::bit_cast<float>(static_cast<std::uint32_t>(key >> 32)); }

// Lowers the distances of slots [begin, end) to their squared distance from p and returns the largest,
// as its bits read as a signed integer: they order non-negative floats as the floats, and the -1 of
// chosen points below all of them. An integer maximum the compiler vectorises; a float one it may not.
PBS_AVX2_CLONES std::int32_t lowerDistances(const CellSortedPoints& grid, std::uint32_t begin, std::uint32_t end,
                                            glm::vec3 p, float* distance) {
  const float* x = grid.x.data();
  const float* y = grid.y.data();
  const float* z = grid.z.data();
  std::int32_t best = std::numeric_limits<std::int32_t>::min();
  for (std::uint32_t s = begin; s < end; ++s) {
    const float dx = x[s] - p.x, dy = y[s] - p.y, dz = z[s] - p.z;
    const float d = std::min(distance[s], dx * dx + dy * dy + dz * dz);  // glm::dot's order of sums
    distance[s] = d;
    best = std::max(best, std::bit_cast<std::int32_t>(d));
  }
  return best;
}

}  // namespace

std::vector<std::uint32_t> orderFarthest(std::span<const glm::vec3> points, std::uint32_t max, std::uint64_t seed) {
  std::vector<std::uint32_t> order;
  if (points.empty() || max == 0) return order;
  const CellSortedPoints grid = sortIntoCells(points, max);
  SeededRandom rng(seed);
  const std::uint32_t first = static_cast<std::uint32_t>(rng.below(points.size()));
  order.push_back(first);

  // Per slot: squared distance to the nearest chosen point; chosen points hold -1 so no update applies.
  std::vector<float> distance(points.size(), std::numeric_limits<float>::infinity());
  distance[grid.slotOf[first]] = -1.0f;

  // Per cell: an upper bound of the heap key of its farthest pool point, 0 when it has none. The heap
  // holds cells, not points: a few cells per chosen point change, and a heap of cells stays small
  // enough for the cache.
  const std::size_t cells = grid.cellStart.size() - 1;
  std::vector<std::uint64_t> cellBest(cells, 0);
  // Rescans a cell after its distances changed: a cell is small, and it was just read anyway. The bound
  // is the farthest distance with the cell's lowest index; which slot holds that distance (the key's
  // index) is only looked for when the cell reaches the top of the heap (exactKey).
  const auto updateCell = [&](std::size_t c, const glm::vec3& chosen) {
    const std::uint32_t begin = grid.cellStart[c];
    const std::int32_t best = lowerDistances(grid, begin, grid.cellStart[c + 1], chosen, distance.data());
    cellBest[c] = best < 0 ? 0 : heapKey(std::bit_cast<float>(best), grid.index[begin]);
  };
  // Slots are in increasing index order within a cell, so the first at the farthest distance holds
  // heapKey's tie rule.
  const auto exactKey = [&](std::size_t c) {
    const std::uint32_t farthest = static_cast<std::uint32_t>(cellBest[c] >> 32);
    std::uint32_t s = grid.cellStart[c];
    while (std::bit_cast<std::uint32_t>(distance[s]) != farthest) ++s;
    return heapKey(distance[s], grid.index[s]);
  };
  using Entry = std::pair<std::uint64_t, std::uint32_t>;  // (cell's key when pushed, cell)
  // By key alone: equal keys hold the same index, so they are entries of one cell (pair's synthesised
  // three-way comparison costs more than the key's).
  const auto byKey = [](const Entry& a, const Entry& b) { return a.first < b.first; };
  std::vector<Entry> heap;
  for (std::uint32_t c = 0; c < cells; ++c) {
    updateCell(c, points[first]);
    if (cellBest[c] != 0) heap.emplace_back(cellBest[c], c);
  }
  std::make_heap(heap.begin(), heap.end(), byKey);

  // Per axis, the squared gap from the chosen point to each layer of cells in its reach: a cell's gap
  // is then the sum of three (summed in glm::dot's order, so it is the very value of gapTo).
  std::array<std::vector<float>, 3> layerGap;
  // Keys only shrink and the heap is not told: each entry is an upper bound of its cell's key, so a
  // top that is current and exact holds the true farthest point; a stale top is pushed back with its
  // current bound, a current one with its exact key when that is lower.
  const auto push = [&](std::uint64_t key, std::uint32_t cell) {
    heap.emplace_back(key, cell);
    std::push_heap(heap.begin(), heap.end(), byKey);
  };
  while (order.size() < max && !heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), byKey);
    const auto [key, cell] = heap.back();
    heap.pop_back();
    if (cellBest[cell] != key) {
      if (cellBest[cell] != 0) push(cellBest[cell], cell);
      continue;
    }
    cellBest[cell] = exactKey(cell);
    if (cellBest[cell] != key) {
      push(cellBest[cell], cell);
      continue;
    }
    const std::uint32_t index = ~static_cast<std::uint32_t>(key);
    const std::uint32_t slot = grid.slotOf[index];
    const float radius2 = distance[slot];
    order.push_back(index);
    distance[slot] = -1.0f;
    if (radius2 == 0.0f) {
      // The farthest pool point is at distance 0, so all are, and stay so: ties go to the lower index,
      // so the rest of the order is the pool in index order. Taken in one pass, as rescanning the
      // chosen point's cell for each of n coincident points would cost n².
      for (std::uint32_t i = 0; i < points.size() && order.size() < max; ++i)
        if (distance[grid.slotOf[i]] >= 0.0f) order.push_back(i);
      break;
    }
    // Only points within the chosen point's own distance can have it as their new nearest.
    const glm::vec3 p = points[index];
    // A relative margin so float rounding never skips a point inside the radius.
    const float reach = std::sqrt(radius2) * 1.0001f;
    const glm::ivec3 lo = grid.cellOf(p - reach);
    const glm::ivec3 hi = grid.cellOf(p + reach);
    const auto gapTo = [&](const glm::ivec3& first, float size) {
      const glm::vec3 boxLo = grid.lo + glm::vec3(first) * grid.cellSize;
      const glm::vec3 gap =
          glm::max(glm::max(boxLo - grid.slack - p, p - (boxLo + size + grid.slack)), glm::vec3(0.0f));
      return glm::dot(gap, gap);
    };
    for (int a = 0; a < 3; ++a) {
      layerGap[a].resize(std::size_t(hi[a] - lo[a] + 1));
      for (int i = lo[a]; i <= hi[a]; ++i) {
        const float boxLo = grid.lo[a] + float(i) * grid.cellSize;
        const float gap =
            std::max(std::max(boxLo - grid.slack - p[a], p[a] - (boxLo + grid.cellSize + grid.slack)), 0.0f);
        layerGap[a][std::size_t(i - lo[a])] = gap * gap;
      }
    }
    const glm::ivec3 blockLo = lo >> kBlockShift, blockHi = hi >> kBlockShift;
    const float blockSize = grid.cellSize * float(1 << kBlockShift);
    for (int bz = blockLo.z; bz <= blockHi.z; ++bz) {
      for (int by = blockLo.y; by <= blockHi.y; ++by) {
        for (int bx = blockLo.x; bx <= blockHi.x; ++bx) {
          const glm::ivec3 block(bx, by, bz);
          if (!grid.blockOccupied[grid.blockLinear(block)] || gapTo(block << kBlockShift, blockSize) > reach * reach)
            continue;
          const glm::ivec3 from = glm::max(lo, block << kBlockShift);
          const glm::ivec3 to = glm::min(hi, ((block + 1) << kBlockShift) - 1);
          for (int z = from.z; z <= to.z; ++z) {
            const float gapZ = layerGap[2][std::size_t(z - lo.z)];
            for (int y = from.y; y <= to.y; ++y) {
              const float gapY = layerGap[1][std::size_t(y - lo.y)];
              // Rounding is monotone, so no cell of the row is nearer than its x gap 0 would make it.
              if (gapY + gapZ > reach * reach) continue;
              const std::size_t row = grid.linear({0, y, z});
              for (int x = from.x; x <= to.x; ++x) {
                // A cell is rescanned only if p can be nearer than some point's current distance: within
                // the chosen point's reach, and nearer than the cell's farthest pool point (cells already
                // covered by earlier choices are skipped; the margin covers the rounding of the squared
                // distances, the slack that of the box).
                const std::size_t c = row + std::size_t(x);
                const float gap2 = layerGap[0][std::size_t(x - lo.x)] + gapY + gapZ;
                if (gap2 <= reach * reach && gap2 < keyDistance(cellBest[c]) * 1.0002f) updateCell(c, p);
              }
            }
          }
        }
      }
    }
    // The chosen point's own entry was consumed; its cell (always within reach) needs a new one.
    const std::uint32_t own = static_cast<std::uint32_t>(grid.linear(grid.cellOf(p)));
    if (cellBest[own] != 0) push(cellBest[own], own);
  }
  return order;
}

}  // namespace pbs
