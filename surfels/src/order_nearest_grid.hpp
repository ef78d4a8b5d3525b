// A hash grid over a growing subset of points for nearest-neighbour queries (dart throwing, metrics).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace pbs {

class NearestPointGrid {
 public:
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

  // `points` is every point that may be inserted; its bounding box fixes the grid's extent.
  explicit NearestPointGrid(std::span<const glm::vec3> points);

  void insert(std::uint32_t index);

  // Squared distance from `query` to the nearest inserted point other than `skip`; +inf when none.
  float nearestSquared(const glm::vec3& query, std::uint32_t skip = kNone) const;

 private:
  // Re-links every inserted point with a cell size matched to the current count.
  void rebuild();
  glm::ivec3 cellOf(const glm::vec3& p) const;
  std::uint32_t slotOf(const glm::ivec3& cell) const;
  void link(std::uint32_t entry);

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
