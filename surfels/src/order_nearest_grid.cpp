// NearestPointGrid: cells hashed into a table (chains of entries); searched in growing shells of cells.
#include "order_nearest_grid.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pbs {

namespace {

// A rebuild happens whenever the count has grown this much: on a surface the spacing then halves.
constexpr std::size_t kGrowth = 4;

}  // namespace

namespace {

// The box and a finiteness flag of `points`, in a form the compiler vectorises: the coordinates read as
// one float array, four points (12 floats) a step, one lane per float of the step.
struct RawBox {
  glm::vec3 lo{0.0f}, hi{0.0f};
  bool finite = true;
};
RawBox rawBox(std::span<const glm::vec3> points) {
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "points are read as a packed float array");
  constexpr std::size_t kLanes = 12;
  const float* f = &points[0].x;
  const std::size_t floats = 3 * points.size();
  std::array<float, kLanes> lo, hi, spread{};
  for (std::size_t j = 0; j < kLanes; ++j) lo[j] = hi[j] = points[0][j % 3];
  // x - x is 0 for a finite x and NaN for an infinite or NaN one, and a NaN sum stays NaN.
  const auto add = [&](std::size_t j, float x) {
    lo[j] = x < lo[j] ? x : lo[j];
    hi[j] = hi[j] < x ? x : hi[j];
    spread[j] += x - x;
  };
  std::size_t i = 0;
  for (; i + kLanes <= floats; i += kLanes)
    for (std::size_t j = 0; j < kLanes; ++j) add(j, f[i + j]);
  for (std::size_t j = 0; i + j < floats; ++j) add(j, f[i + j]);
  RawBox box{points[0], points[0], true};
  for (std::size_t j = 0; j < kLanes; ++j) {
    box.lo[j % 3] = std::min(box.lo[j % 3], lo[j]);
    box.hi[j % 3] = std::max(box.hi[j % 3], hi[j]);
    box.finite &= spread[j] == 0.0f;
  }
  return box;
}

}  // namespace

OrderableBox orderableBox(std::span<const glm::vec3> points, const char* who, std::span<const std::uint32_t> names) {
  OrderableBox box;
  if (points.empty()) return box;
  const RawBox raw = rawBox(points);
  const auto fail = [&](std::size_t i, const char* problem) {
    std::string message(who);
    message.append(": point ").append(std::to_string(names.empty() ? i : names[i])).append(problem);
    throw std::invalid_argument(message);
  };
  if (!raw.finite) {
    for (std::size_t i = 0; i < points.size(); ++i)
      if (!std::isfinite(points[i].x) || !std::isfinite(points[i].y) || !std::isfinite(points[i].z))
        fail(i, " is not finite");
  }
  const glm::vec3 extent = raw.hi - raw.lo;
  if (std::max({extent.x, extent.y, extent.z}) > kMaxOrderableExtent) {
    // Point 0 lies in the box, so some point is more than half the extent away from it.
    std::size_t far = 0;
    while (far + 1 < points.size() &&
           !glm::any(glm::greaterThan(glm::abs(points[far] - points[0]), glm::vec3(0.5f * kMaxOrderableExtent))))
      ++far;
    fail(far, " makes the points span more than 1e18: squared distances would overflow float");
  }
  box.lo = raw.lo;
  if (std::max({extent.x, extent.y, extent.z}) >= std::numeric_limits<float>::min()) box.extent = extent;
  return box;
}

NearestPointGrid::NearestPointGrid(std::span<const glm::vec3> points, const char* who) : points_(points) {
  const OrderableBox box = orderableBox(points, who);
  lo_ = box.lo;
  extent_ = box.extent;
}

NearestPointGrid::NearestPointGrid(std::span<const glm::vec3> points, std::span<const std::uint32_t> insertable,
                                   const char* who)
    : points_(points) {
  std::vector<glm::vec3> gathered(insertable.size());
  for (std::size_t i = 0; i < insertable.size(); ++i) gathered[i] = points[insertable[i]];
  const OrderableBox box = orderableBox(gathered, who, insertable);
  lo_ = box.lo;
  extent_ = box.extent;
}

glm::ivec3 NearestPointGrid::cellOf(const glm::vec3& p) const {
  const glm::ivec3 cell(glm::floor((p - lo_) / cellSize_));
  return glm::clamp(cell, glm::ivec3(0), dims_ - 1);
}

std::uint32_t NearestPointGrid::slotOf(const glm::ivec3& cell) const {
  const std::uint32_t h = static_cast<std::uint32_t>(cell.x) * 73856093u ^
                          static_cast<std::uint32_t>(cell.y) * 19349663u ^
                          static_cast<std::uint32_t>(cell.z) * 83492791u;
  return h & static_cast<std::uint32_t>(head_.size() - 1);
}

void NearestPointGrid::link(std::uint32_t entry) {
  const std::uint32_t slot = slotOf(cellOf(position_[entry]));
  next_[entry] = head_[slot];
  head_[slot] = static_cast<std::int32_t>(entry);
}

void NearestPointGrid::rebuild() {
  const std::size_t count = inserted_.size();
  rebuildAt_ = std::max<std::size_t>(16, kGrowth * count);
  head_.assign(std::bit_ceil(rebuildAt_), -1);
  next_.resize(count);
  const float maxExtent = std::max({extent_.x, extent_.y, extent_.z});
  cellSize_ = crowdingCellSize(maxExtent, count, [&](float size) {
    cellSize_ = size;
    dims_ = glm::min(glm::ivec3(glm::floor(extent_ / cellSize_)) + 1, glm::ivec3(kMaxCellsPerAxis));
    std::fill(head_.begin(), head_.end(), -1);
    for (std::uint32_t e = 0; e < count; ++e) link(e);
    // Occupied slots stand for occupied cells (the table has four slots a point, so few cells share one).
    return std::size_t(std::count_if(head_.begin(), head_.end(), [](std::int32_t e) { return e >= 0; }));
  });
}

void NearestPointGrid::insert(std::uint32_t index) {
  inserted_.push_back(index);
  position_.push_back(points_[index]);
  if (inserted_.size() >= rebuildAt_) {
    rebuild();
    return;
  }
  next_.push_back(-1);
  link(static_cast<std::uint32_t>(inserted_.size() - 1));
}

float NearestPointGrid::nearestByScan(const glm::vec3& query, std::uint32_t skip, float best) const {
  for (std::size_t e = 0; e < position_.size() && best > 0.0f; ++e) {
    if (inserted_[e] == skip) continue;
    const glm::vec3 d = position_[e] - query;
    best = std::min(best, glm::dot(d, d));
  }
  return best;
}

float NearestPointGrid::nearestSquared(const glm::vec3& query, std::uint32_t skip, float limitSquared) const {
  float best = std::numeric_limits<float>::infinity();
  if (inserted_.empty()) return best;
  const glm::ivec3 c = cellOf(query);
  const auto visit = [&](int x, int y, int z) {
    // Skip cells that cannot hold anything nearer than the best so far (cheaper than their memory).
    const glm::vec3 boxLo = lo_ + glm::vec3(x, y, z) * cellSize_;
    const glm::vec3 gap = glm::max(glm::max(boxLo - query, query - (boxLo + cellSize_)), glm::vec3(0.0f));
    if (glm::dot(gap, gap) > std::min(best, limitSquared)) return;
    for (std::int32_t e = head_[slotOf({x, y, z})]; e >= 0; e = next_[e]) {
      const std::uint32_t index = inserted_[e];
      if (index == skip) continue;
      const glm::vec3 d = position_[e] - query;
      best = std::min(best, glm::dot(d, d));
      // Nothing is nearer than 0: without this, n coincident points cost n per query (n² in all).
      if (best == 0.0f) return;
    }
  };
  const glm::ivec3 far = glm::max(c, dims_ - 1 - c);
  const int lastShell = std::max({far.x, far.y, far.z});
  // Shells grow as s²: a query far from every point (an outlier's, or one in empty space of cells shrunk to
  // crowded points) reads every point instead once the shells would visit more cells than there are points.
  const auto cellsWithin = [&](const glm::ivec3& lo, const glm::ivec3& hi) {
    const glm::dvec3 side = glm::dvec3(hi - lo + 1);
    return side.x * side.y * side.z;
  };
  const double cellBudget = double(inserted_.size()) + 64.0;
  for (int s = 0; s <= lastShell; ++s) {
    const glm::ivec3 lo = glm::max(c - s, glm::ivec3(0));
    const glm::ivec3 hi = glm::min(c + s, dims_ - 1);
    if (cellsWithin(lo, hi) > cellBudget) return nearestByScan(query, skip, best);
    for (int z = lo.z; z <= hi.z; ++z) {
      for (int y = lo.y; y <= hi.y; ++y) {
        if (std::abs(z - c.z) == s || std::abs(y - c.y) == s) {
          for (int x = lo.x; x <= hi.x; ++x) visit(x, y, z);
        } else {
          if (c.x - s >= 0) visit(c.x - s, y, z);
          if (c.x + s < dims_.x) visit(c.x + s, y, z);
        }
      }
    }
    // Every point outside the shells searched so far is at least s cells away.
    const float reach = static_cast<float>(s) * cellSize_;
    if (std::min(best, limitSquared) <= reach * reach) break;
  }
  return best;
}

}  // namespace pbs
