// A hash grid over a growing subset of points for nearest-neighbour queries (dart throwing, metrics).
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace pbs {

// The bounding box of points the orderings and metrics can measure. Throws std::invalid_argument,
// naming `who` and the first offending index, for a non-finite coordinate (it has no distances) or a
// box wider than kMaxOrderableExtent (squared distances would overflow float). A box narrower than
// float's smallest normal number comes back as a single point: its squared distances underflow to 0
// anyway, and cells sized from it would be 0 (divisions by zero, endless cell-size loops). With
// `names`, points[i] is the caller's point names[i], and messages name that.
struct OrderableBox {
  glm::vec3 lo{0.0f};
  glm::vec3 extent{0.0f};
};
inline constexpr float kMaxOrderableExtent = 1e18f;  // 3·(1e18)² stays below FLT_MAX ≈ 3.4e38
OrderableBox orderableBox(std::span<const glm::vec3> points, const char* who,
                          std::span<const std::uint32_t> names = {});

// Cells per axis are capped so cell coordinates (and keys or hashes made of them) stay well inside 32 bits.
inline constexpr int kMaxCellsPerAxis = 1 << 20;

// The cells of the nearest-point searches (NearestPointGrid, allNearestSquared), for `count` points in a box
// `maxExtent` wide: two spacings of points spread over a surface as wide as the box, which keeps a typical
// nearest neighbour within the block of cells around a point's own. Points that fill a small part of the box
// (the buildings of a city block, a few parts far apart) crowd its cells, so the size shrinks by the surface's
// rule, at most three times and to no less than the box over kMaxCellsPerAxis − 1, until occupied cells hold
// four points on average. `occupiedCells(size)` sorts the points into cells of that size and returns how many
// cells it occupied; its last call is at the size returned.
template <class OccupiedCells>
float crowdingCellSize(float maxExtent, std::size_t count, OccupiedCells&& occupiedCells) {
  constexpr double kCrowdedCell = 4.0;
  constexpr int kMaxShrinks = 3;
  const float smallest = maxExtent / static_cast<float>(kMaxCellsPerAxis - 1);
  float size = maxExtent > 0.0f ? 2.0f * maxExtent / std::sqrt(static_cast<float>(count)) : 1.0f;
  for (int attempt = 0;; ++attempt) {
    size = std::max(size, smallest);
    const std::size_t occupied = occupiedCells(size);
    if (attempt == kMaxShrinks || size <= smallest) return size;
    const double crowding = occupied > 0 ? double(count) / double(occupied) : 0.0;
    if (crowding <= kCrowdedCell) return size;
    size *= static_cast<float>(std::sqrt(kCrowdedCell / crowding));
  }
}

class NearestPointGrid {
 public:
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

  // `points` is every point that may be inserted; its bounding box fixes the grid's extent. Throws
  // std::invalid_argument (see orderableBox) for points it cannot measure.
  NearestPointGrid(std::span<const glm::vec3> points, const char* who);
  // Only the points `insertable` names may be inserted, and only their box is measured (and checked):
  // a metric over a prefix of an order then pays for the prefix, not for every candidate.
  NearestPointGrid(std::span<const glm::vec3> points, std::span<const std::uint32_t> insertable, const char* who);

  void insert(std::uint32_t index);

  // Squared distance from `query` to the nearest inserted point other than `skip`; +inf when none. With
  // `limitSquared`, the search stops at that squared distance: nearer points are found exactly, and a value
  // above the limit (+inf or a farther point's) says none is within it.
  float nearestSquared(const glm::vec3& query, std::uint32_t skip = kNone,
                       float limitSquared = std::numeric_limits<float>::infinity()) const;

 private:
  // Re-links every inserted point with a cell size matched to the current count.
  void rebuild();
  glm::ivec3 cellOf(const glm::vec3& p) const;
  std::uint32_t slotOf(const glm::ivec3& cell) const;
  void link(std::uint32_t entry);
  // min(best, the squared distance to the nearest inserted point other than `skip`), every point read.
  float nearestByScan(const glm::vec3& query, std::uint32_t skip, float best) const;

  std::span<const glm::vec3> points_;
  glm::vec3 lo_{0.0f};
  glm::vec3 extent_{0.0f};
  float cellSize_ = 1.0f;
  glm::ivec3 dims_{1};
  std::size_t rebuildAt_ = 0;
  std::vector<std::uint32_t> inserted_;  // point indices in insertion order
  std::vector<glm::vec3> position_;      // per entry: a copy of its point, for locality in queries
  std::vector<std::int32_t> head_;       // per hash slot: first entry of its chain, or -1
  std::vector<std::int32_t> next_;       // per entry: the next entry in its slot's chain, or -1
};

}  // namespace pbs
