// allNearestSquared: the points sorted into cells, and each cell's points compared with every point of the
// 3×3×3 block of cells around it. A query of NearestPointGrid pays for its 27 cells' hashes, chains and bounds
// per point (about 400 ns each on surfelize's arrays); here the cells are sorted so that a block is nine runs
// of one array, found once per cell, and four of the cell's points are compared with each of them at once.
#include "all_nearest_neighbours.hpp"

#include "order_nearest_grid.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>

namespace pbs {
namespace {

// A cell or block crowded beyond these (coincident points, clusters the shrinks could not part) is left to
// NearestPointGrid, whose queries prune by distance and stop at 0, instead of comparing all its pairs.
constexpr std::size_t kMostInACell = 64;
constexpr std::size_t kMostInABlock = 1024;
// Points left without an answer are compared with every point while there are at most this many.
constexpr std::size_t kMostCompared = 64;
// A block holds every point nearer than one cell to a point of its middle cell. The margin covers the float
// rounding of a squared distance (a few parts in 10^7; cell coordinates are computed in double).
constexpr double kExactReach = 1.0 - 1e-5;
constexpr std::uint32_t kNoCell = std::numeric_limits<std::uint32_t>::max();

// The occupied cells, numbered in the order they first appear, found by key in an open-addressing table.
class CellNumbers {
 public:
  explicit CellNumbers(std::size_t points)
      : slots_(std::bit_ceil(2 * points + 2)), shift_(64 - std::countr_zero(slots_.size())) {}

  // No cell, the table's memory kept.
  void clear() {
    std::fill(slots_.begin(), slots_.end(), Slot{});
    keys_.clear();
  }

  // The cell's number; a new cell gets the next one.
  std::uint32_t add(std::int64_t key) {
    for (std::size_t s = slotOf(key);; s = (s + 1) & (slots_.size() - 1)) {
      Slot& slot = slots_[s];
      if (slot.number == kNoCell) {
        slot = {key, std::uint32_t(keys_.size())};
        keys_.push_back(key);
        return slot.number;
      }
      if (slot.key == key) return slot.number;
    }
  }
  std::size_t size() const { return keys_.size(); }
  // Per number, the cell's key.
  const std::vector<std::int64_t>& keys() const { return keys_; }

 private:
  struct Slot {
    std::int64_t key = 0;
    std::uint32_t number = kNoCell;
  };
  std::size_t slotOf(std::int64_t key) const {
    return std::size_t((std::uint64_t(key) * 0x9E3779B97F4A7C15ull) >> shift_);
  }

  std::vector<Slot> slots_;  // at least twice as many as points, so probes stay short
  int shift_;
  std::vector<std::int64_t> keys_;
};

// The points sorted by cell key, one array per coordinate (the comparisons read them as streams). Keys are
// x + y·2^21 + z·2^42 for cell coordinates below 2^20, so the neighbour at (dx, dy, dz) has the key
// key + dx + dy·2^21 + dz·2^42, and a neighbour past the grid's edge gets a key no cell has (a field of
// 2^21 − 1 or a negative key): a row of three neighbours is one interval of keys, hence of cells.
struct SortedCells {
  double size = 1.0;                 // a cell's side
  std::vector<std::int64_t> keys;    // per cell, ascending
  std::vector<std::uint32_t> first;  // per cell, its first point; one more at the end
  std::vector<float> x, y, z;        // per point
  std::vector<std::uint32_t> index;  // per point: the caller's
};

constexpr int kKeyShift = 21;
static_assert(kMaxCellsPerAxis < (1 << kKeyShift) - 1, "a field of all ones names no cell");

std::int64_t cellKey(const glm::ivec3& c) {
  return std::int64_t(c.x) | std::int64_t(c.y) << kKeyShift | std::int64_t(c.z) << (2 * kKeyShift);
}

// The points sorted into cells of crowdingCellSize (as NearestPointGrid's).
SortedCells sortByCell(std::span<const glm::vec3> points, const OrderableBox& box) {
  const std::size_t n = points.size();
  std::vector<std::uint32_t> cellOf(n);
  CellNumbers numbers(n);
  const float maxExtent = std::max({box.extent.x, box.extent.y, box.extent.z});
  const float size = crowdingCellSize(maxExtent, n, [&](float tried) {
    const glm::ivec3 dims =
        glm::min(glm::ivec3(glm::floor(glm::dvec3(box.extent) / double(tried))) + 1, glm::ivec3(kMaxCellsPerAxis));
    numbers.clear();
    for (std::size_t i = 0; i < n; ++i) {
      const glm::dvec3 at = glm::floor((glm::dvec3(points[i]) - glm::dvec3(box.lo)) / double(tried));
      cellOf[i] = numbers.add(cellKey(glm::clamp(glm::ivec3(at), glm::ivec3(0), dims - 1)));
    }
    return numbers.size();
  });

  // Cells renumbered by key, then the points counted into them.
  const std::vector<std::int64_t>& keys = numbers.keys();
  std::vector<std::pair<std::int64_t, std::uint32_t>> byKey(keys.size());
  for (std::uint32_t c = 0; c < byKey.size(); ++c) byKey[c] = {keys[c], c};
  std::sort(byKey.begin(), byKey.end());
  std::vector<std::uint32_t> rank(keys.size());
  SortedCells cells;
  cells.size = size;
  cells.keys.resize(keys.size());
  for (std::uint32_t r = 0; r < byKey.size(); ++r) {
    rank[byKey[r].second] = r;
    cells.keys[r] = byKey[r].first;
  }
  cells.first.assign(keys.size() + 1, 0);
  for (std::uint32_t& c : cellOf) ++cells.first[(c = rank[c]) + 1];
  for (std::size_t c = 1; c < cells.first.size(); ++c) cells.first[c] += cells.first[c - 1];
  std::vector<std::uint32_t> next(cells.first.begin(), cells.first.end() - 1);
  cells.x.resize(n);
  cells.y.resize(n);
  cells.z.resize(n);
  cells.index.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t t = next[cellOf[i]]++;
    cells.x[t] = points[i].x;
    cells.y[t] = points[i].y;
    cells.z[t] = points[i].z;
    cells.index[t] = i;
  }
  return cells;
}

typedef float Float4 __attribute__((vector_size(4 * sizeof(float))));
typedef std::int32_t Int4 __attribute__((vector_size(4 * sizeof(std::int32_t))));

// Entries [first, end) of the sorted points.
struct Run {
  std::uint32_t first = 0, end = 0;
};

// The points of the 3×3×3 block of cells around each cell in turn, as nine runs of points (one per row of
// three cells along x). Cells are visited in key order, so each row's first cell only moves forward.
class BlockRows {
 public:
  explicit BlockRows(const SortedCells& cells) : cells_(cells) { cursor_.fill(0); }

  // The runs of the block around cell `c`; cells must come in ascending order.
  const std::array<Run, 9>& around(std::uint32_t c) {
    const std::int64_t key = cells_.keys[c];
    for (int row = 0; row < 9; ++row) {
      const std::int64_t middle =
          key + (std::int64_t(row % 3 - 1) << kKeyShift) + (std::int64_t(row / 3 - 1) << (2 * kKeyShift));
      std::uint32_t& lo = cursor_[row];
      while (lo < cells_.keys.size() && cells_.keys[lo] < middle - 1) ++lo;
      std::uint32_t hi = lo;
      while (hi < cells_.keys.size() && cells_.keys[hi] <= middle + 1) ++hi;
      runs_[row] = {cells_.first[lo], cells_.first[hi]};
    }
    return runs_;
  }

 private:
  const SortedCells& cells_;
  std::array<std::uint32_t, 9> cursor_;
  std::array<Run, 9> runs_;
};

// The squared distances from the entries `queries` (one a lane) to the nearest other point of the runs:
// each point of the runs is compared with four queries at once. d = p − q and (dx² + dy²) + dz² are
// glm::dot's, and each lane rounds as scalar code does; min is exact in any order, so every lane holds the
// scalar search's value to the bit.
Float4 nearestOfFour(const SortedCells& cells, const Int4& queries, std::span<const Run> runs) {
  const auto gather = [&](const std::vector<float>& column) {
    return Float4{column[queries[0]], column[queries[1]], column[queries[2]], column[queries[3]]};
  };
  const Float4 qx = gather(cells.x), qy = gather(cells.y), qz = gather(cells.z);
  constexpr float kInf = std::numeric_limits<float>::infinity();
  Float4 best = {kInf, kInf, kInf, kInf};
  for (const Run& run : runs) {
    for (std::uint32_t j = run.first; j < run.end; ++j) {
      const Float4 dx = cells.x[j] - qx, dy = cells.y[j] - qy, dz = cells.z[j] - qz;
      Float4 d2 = (dx * dx + dy * dy) + dz * dz;
      d2 = queries == std::int32_t(j) ? kInf : d2;
      best = d2 < best ? d2 : best;
    }
  }
  return best;
}

// The entries entryAt(first) to entryAt(first + 3), one a lane; past `end` the last one again.
template <class EntryAt>
Int4 fourOf(std::size_t first, std::size_t end, EntryAt entryAt) {
  Int4 four;
  for (std::size_t lane = 0; lane < 4; ++lane) four[lane] = std::int32_t(entryAt(std::min(first + lane, end - 1)));
  return four;
}

}  // namespace

std::vector<float> allNearestSquared(std::span<const glm::vec3> points, const char* who,
                                     std::span<const std::uint32_t> names) {
  const OrderableBox box = orderableBox(points, who, names);
  std::vector<float> nearest(points.size(), std::numeric_limits<float>::infinity());
  if (points.size() < 2) return nearest;

  const SortedCells cells = sortByCell(points, box);
  const double reach = kExactReach * cells.size;
  std::vector<std::uint32_t> unanswered;  // entries of `cells`
  BlockRows blocks(cells);
  for (std::uint32_t c = 0; c + 1 < cells.first.size(); ++c) {
    const std::uint32_t first = cells.first[c], end = cells.first[c + 1];
    const std::array<Run, 9>& runs = blocks.around(c);
    std::size_t inBlock = 0;
    for (const Run& run : runs) inBlock += run.end - run.first;
    if (end - first > kMostInACell || inBlock > kMostInABlock) {
      for (std::uint32_t t = first; t < end; ++t) unanswered.push_back(t);
      continue;
    }
    for (std::uint32_t group = first; group < end; group += 4) {
      const Float4 best = nearestOfFour(cells, fourOf(group, end, [](std::size_t t) { return t; }), runs);
      for (std::uint32_t t = group; t < std::min(group + 4, end); ++t) {
        if (double(best[t - group]) <= reach * reach)
          nearest[cells.index[t]] = best[t - group];
        else
          unanswered.push_back(t);
      }
    }
  }
  // Points with no neighbour within a cell (outliers, sparse parts) and crowded cells: a few are compared
  // with every point, more are searched in NearestPointGrid's shells.
  if (unanswered.size() <= kMostCompared) {
    const Run all{0, std::uint32_t(points.size())};
    for (std::size_t k = 0; k < unanswered.size(); k += 4) {
      const Float4 best =
          nearestOfFour(cells, fourOf(k, unanswered.size(), [&](std::size_t u) { return unanswered[u]; }), {&all, 1});
      for (std::size_t lane = 0; lane < 4 && k + lane < unanswered.size(); ++lane)
        nearest[cells.index[unanswered[k + lane]]] = best[lane];
    }
  } else {
    NearestPointGrid grid(points, who);
    for (std::uint32_t i = 0; i < points.size(); ++i) grid.insert(i);
    for (std::uint32_t t : unanswered)
      nearest[cells.index[t]] = grid.nearestSquared(points[cells.index[t]], cells.index[t]);
  }
  return nearest;
}

}  // namespace pbs
