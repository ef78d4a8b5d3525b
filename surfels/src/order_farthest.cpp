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

constexpr int kBlockShift = 2;  // blocks of 4 × 4 × 4 cells
constexpr int kBlockMask = (1 << kBlockShift) - 1;
constexpr int kCellsPerBlockShift = 3 * kBlockShift;

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
  std::size_t blockLinear(const glm::ivec3& b) const {
    return (static_cast<std::size_t>(b.z) * blockDims.y + b.y) * blockDims.x + b.x;
  }
  // Cells are numbered block by block, so that the per-cell arrays a search reads for one block
  // (cellBest, cellStart) lie together, not in 16 rows of the grid. `block` is blockLinear(c >> kBlockShift);
  // within a block, x varies fastest, so the cells of a row are consecutive.
  static std::size_t cellIndex(std::size_t block, const glm::ivec3& c) {
    return (block << kCellsPerBlockShift) +
           std::size_t((((c.z & kBlockMask) << kBlockShift) + (c.y & kBlockMask)) << kBlockShift) +
           std::size_t(c.x & kBlockMask);
  }
};

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
    for (;;) {  // counting the cells that fill out the last block on each axis
      const glm::dvec3 blocks(((dimsFor(extent, grid.cellSize) - 1) >> kBlockShift) + 1);
      if (blocks.x * blocks.y * blocks.z * double(1 << kCellsPerBlockShift) <= cellLimit) break;
      grid.cellSize *= 1.25f;
    }
  }
  grid.dims = dimsFor(extent, grid.cellSize);
  const float magnitude =
      std::max({std::abs(box.lo.x), std::abs(box.lo.y), std::abs(box.lo.z), std::abs(box.lo.x + extent.x),
                std::abs(box.lo.y + extent.y), std::abs(box.lo.z + extent.z)});
  grid.slack = 1e-3f * grid.cellSize + 16.0f * std::numeric_limits<float>::epsilon() * magnitude;
  grid.blockDims = ((grid.dims - 1) >> kBlockShift) + 1;
  const std::size_t blocks = static_cast<std::size_t>(grid.blockDims.x) * grid.blockDims.y * grid.blockDims.z;
  const std::size_t cells = blocks << kCellsPerBlockShift;
  std::vector<std::uint32_t> cellOfPoint(points.size());
  grid.cellStart.assign(cells + 1, 0);
  grid.blockOccupied.assign(blocks, 0);
  {
    // grid.cellOf for points of the box, where p - lo is not negative, so truncation is the floor (floor
    // itself is a long sequence on baseline x86-64). The grid's fields are copied: the byte stores
    // below may alias anything, and would have them reloaded per point.
    const glm::vec3 lo = grid.lo;
    const float cellSize = grid.cellSize;
    const glm::ivec3 dims = grid.dims;
    std::uint32_t* count = grid.cellStart.data() + 1;
    std::uint8_t* blockOccupied = grid.blockOccupied.data();
    for (std::size_t i = 0; i < points.size(); ++i) {
      const glm::vec3 q = (points[i] - lo) / cellSize;
      const glm::ivec3 cell(std::min(int(q.x), dims.x - 1), std::min(int(q.y), dims.y - 1),
                            std::min(int(q.z), dims.z - 1));
      const std::size_t block = grid.blockLinear(cell >> kBlockShift);
      const auto c = static_cast<std::uint32_t>(CellSortedPoints::cellIndex(block, cell));
      cellOfPoint[i] = c;
      ++count[c];
      blockOccupied[block] = 1;
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

// A binary max-heap of (key, cell) entries whose top can be replaced in one sift-down: a stale top is
// put back with its cell's current key, and a chosen point's cell with its new one, where std's heap
// would pop and then push (two passes). Ordered by key alone (pair's synthesised three-way comparison
// costs more): cells whose keys tie leave in either order, and a choice waits for the exact key, which
// no other cell's can equal.
class CellHeap {
 public:
  struct Entry {
    std::uint64_t key;  // the cell's key when it was put in
    std::uint32_t cell;
  };
  void add(Entry e) { entries_.push_back(e); }
  void build() {
    std::make_heap(entries_.begin(), entries_.end(), [](const Entry& a, const Entry& b) { return a.key < b.key; });
  }
  bool empty() const { return entries_.empty(); }
  const Entry& top() const { return entries_.front(); }
  // The largest key below the top's (0 when the top is alone).
  std::uint64_t nextKey() const {
    const std::size_t n = entries_.size();
    if (n < 2) return 0;
    return n == 2 ? entries_[1].key : std::max(entries_[1].key, entries_[2].key);
  }
  // Puts the top back with `key`, or drops it where key is 0 (its cell has no pool point left).
  void resetTop(std::uint64_t key) {
    if (key != 0) {
      siftDown({key, entries_.front().cell});
      return;
    }
    const Entry last = entries_.back();
    entries_.pop_back();
    if (!entries_.empty()) siftDown(last);
  }

 private:
  // Puts e at the root and moves it down to where it belongs.
  void siftDown(Entry e) {
    const std::size_t n = entries_.size();
    std::size_t i = 0;
    for (;;) {
      std::size_t child = 2 * i + 1;
      if (child >= n) break;
      if (child + 1 < n && entries_[child + 1].key > entries_[child].key) ++child;
      if (entries_[child].key <= e.key) break;
      entries_[i] = entries_[child];
      i = child;
    }
    entries_[i] = e;
  }
  std::vector<Entry> entries_;
};

// Lowers the distances of slots [begin, end) to their squared distance from p and returns the largest,
// as its bits read as a signed integer: they order non-negative floats as the floats, and the -1 of
// chosen points below all of them. An integer maximum the compiler vectorises; a float one it may not.
PBS_CLONE_INLINE std::int32_t lowerDistances(const CellSortedPoints& grid, std::uint32_t begin, std::uint32_t end,
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

// Cloned for AVX2 with the distance updates inlined: a rescanned cell holds a few points, so a call per
// cell (to a clone of its own) cost more than the loop.
PBS_AVX2_CLONES std::vector<std::uint32_t> orderFarthest(std::span<const glm::vec3> points, std::uint32_t max,
                                                         std::uint64_t seed) {
  std::vector<std::uint32_t> order;  // the chosen points' slots, their indices at the end
  if (points.empty() || max == 0) return order;
  const CellSortedPoints grid = sortIntoCells(points, max);
  SeededRandom rng(seed);
  const std::uint32_t first = static_cast<std::uint32_t>(rng.below(points.size()));
  order.push_back(grid.slotOf[first]);

  // Per slot: squared distance to the nearest chosen point; chosen points hold -1 so no update applies.
  std::vector<float> distance(points.size(), std::numeric_limits<float>::infinity());
  distance[grid.slotOf[first]] = -1.0f;

  // Per cell: an upper bound of the heap key of its farthest pool point, 0 when it has none. The heap
  // holds cells, not points: a few cells per chosen point change, and a heap of cells stays small
  // enough for the cache.
  const std::size_t cells = grid.cellStart.size() - 1;
  std::vector<std::uint64_t> cellBest(cells, 0);
  // Rescans a cell after its distances changed: a cell is small, and it was just read anyway. The bound
  // is the farthest distance with the lowest index there can be (index 0: all ones in the key's low
  // half); which slot holds that distance, and its index, is only looked for when the cell reaches the
  // top of the heap (exactSlot). Reading the cell's first index here instead cost a cache miss per cell.
  const auto updateCell = [&](std::size_t c, const glm::vec3& chosen) {
    const std::int32_t best = lowerDistances(grid, grid.cellStart[c], grid.cellStart[c + 1], chosen, distance.data());
    cellBest[c] = best < 0 ? 0 : heapKey(std::bit_cast<float>(best), 0);
  };
  // The slot of the cell's farthest pool point: slots are in increasing index order within a cell, so
  // the first at the farthest distance holds heapKey's tie rule.
  const auto exactSlot = [&](std::size_t c) {
    const std::uint32_t farthest = static_cast<std::uint32_t>(cellBest[c] >> 32);
    std::uint32_t s = grid.cellStart[c];
    while (std::bit_cast<std::uint32_t>(distance[s]) != farthest) ++s;
    return s;
  };
  CellHeap heap;
  for (std::uint32_t c = 0; c < cells; ++c) {
    updateCell(c, points[first]);
    if (cellBest[c] != 0) heap.add({cellBest[c], c});
  }
  heap.build();

  // Per axis, the squared gap from the chosen point to each layer of cells in its reach: a cell's gap
  // is then the sum of three (summed in glm::dot's order, so it is the very value of gapTo).
  std::array<std::vector<float>, 3> layerGap;
  // Distances only shrink and the heap is not told: each entry is an upper bound of its cell's key, so a
  // top whose exact key is no lower than the next entry holds the true farthest point; a stale top is
  // put back with its current bound, a current one with its exact key when another entry is higher.
  while (order.size() < max && !heap.empty()) {
    const auto [key, cell] = heap.top();
    if (cellBest[cell] != key) {
      heap.resetTop(cellBest[cell]);
      continue;
    }
    // The top cell's exact key is the farthest of all once no other entry's bound exceeds it. Its index
    // (a cache miss) is read only where another entry's distance is as large, and the order is kept as
    // slots until the end.
    const std::uint32_t slot = exactSlot(cell);
    if (const std::uint64_t next = heap.nextKey(); (next >> 32) >= (key >> 32)) {
      const std::uint64_t exact = heapKey(distance[slot], grid.index[slot]);
      cellBest[cell] = exact;
      if (next > exact) {
        heap.resetTop(exact);
        continue;
      }
    }
    const float radius2 = distance[slot];
    order.push_back(slot);
    distance[slot] = -1.0f;
    if (radius2 == 0.0f) {
      // The farthest pool point is at distance 0, so all are, and stay so: ties go to the lower index,
      // so the rest of the order is the pool in index order. Taken in one pass, as rescanning the
      // chosen point's cell for each of n coincident points would cost n².
      for (std::uint32_t i = 0; i < points.size() && order.size() < max; ++i)
        if (distance[grid.slotOf[i]] >= 0.0f) order.push_back(grid.slotOf[i]);
      break;
    }
    // Only points within the chosen point's own distance can have it as their new nearest.
    const glm::vec3 p(grid.x[slot], grid.y[slot], grid.z[slot]);
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
          const std::size_t blockIndex = grid.blockLinear(block);
          if (!grid.blockOccupied[blockIndex] || gapTo(block << kBlockShift, blockSize) > reach * reach) continue;
          const glm::ivec3 from = glm::max(lo, block << kBlockShift);
          const glm::ivec3 to = glm::min(hi, ((block + 1) << kBlockShift) - 1);
          for (int z = from.z; z <= to.z; ++z) {
            const float gapZ = layerGap[2][std::size_t(z - lo.z)];
            for (int y = from.y; y <= to.y; ++y) {
              const float gapY = layerGap[1][std::size_t(y - lo.y)];
              // Rounding is monotone, so no cell of the row is nearer than its x gap 0 would make it.
              if (gapY + gapZ > reach * reach) continue;
              const std::size_t row = CellSortedPoints::cellIndex(blockIndex, {0, y, z});
              for (int x = from.x; x <= to.x; ++x) {
                // A cell is rescanned only if p can be nearer than some point's current distance: within
                // the chosen point's reach, and nearer than the cell's farthest pool point (cells already
                // covered by earlier choices are skipped; the margin covers the rounding of the squared
                // distances, the slack that of the box).
                const std::size_t c = row + std::size_t(x & kBlockMask);
                const float gap2 = layerGap[0][std::size_t(x - lo.x)] + gapY + gapZ;
                if (gap2 <= reach * reach && gap2 < keyDistance(cellBest[c]) * 1.0002f) updateCell(c, p);
              }
            }
          }
        }
      }
    }
    // The top is the chosen point's cell (always within reach, so rescanned): its entry takes the new key.
    heap.resetTop(cellBest[cell]);
  }
  for (std::uint32_t& chosen : order) chosen = grid.index[chosen];
  return order;
}

}  // namespace pbs
