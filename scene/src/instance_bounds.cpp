// Branch-and-bound over a tree of point clusters for exact transformed bounds: a box bounds what the
// points under it can reach along an axis, the points of the most promising cluster give a value that
// is reached, and only the boxes whose bound beats it are opened.
#include "instance_bounds.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace pbs::detail {
namespace {

// Spreads the low 10 bits of v so that two zero bits separate each (for a 30-bit Morton code).
std::uint32_t spreadBits(std::uint32_t v) {
  v &= 0x3ffu;
  v = (v | (v << 16)) & 0x030000ffu;
  v = (v | (v << 8)) & 0x0300f00fu;
  v = (v | (v << 4)) & 0x030c30c3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}

// a·p + t, summed in this order: the one formula for points and for box corners.
double pointValue(const glm::dvec3& a, double t, const glm::vec3& p) {
  return a.x * double(p.x) + a.y * double(p.y) + a.z * double(p.z) + t;
}

// The largest pointValue of any point in the box [lo, hi]: the same formula at the corner each term's
// sign favours. Rounding to nearest is monotonic, so no point of the box can round to more: a bound
// with no slack, and a box whose bound only ties the best value so far can be skipped (the flat roofs
// and floors of a city's meshes tie in every cluster that touches them).
double boxSupport(const glm::dvec3& a, double t, const glm::vec3& lo, const glm::vec3& hi) {
  return pointValue(a, t, glm::vec3(a.x >= 0.0 ? hi.x : lo.x, a.y >= 0.0 ? hi.y : lo.y, a.z >= 0.0 ? hi.z : lo.z));
}

// max of a·p + t over the points of cluster k.
double clusterMaximum(const ClusteredPoints& c, std::size_t k, const glm::dvec3& a, double t) {
  double best = -std::numeric_limits<double>::infinity();
  const std::size_t end = std::min(c.points.size(), (k + 1) * ClusteredPoints::kClusterSize);
  for (std::size_t i = k * ClusteredPoints::kClusterSize; i < end; ++i) best = std::max(best, pointValue(a, t, c.points[i]));
  return best;
}

// max over all points of a·p + t, exactly. First down the tree along the largest box bound at each
// level to one cluster: its points nearly always hold the maximum. Then every box whose bound could
// still beat that value is opened, depth first; the others are skipped with everything under them.
double exactMaximum(const ClusteredPoints& c, const glm::dvec3& a, double t) {
  constexpr std::size_t kFanout = ClusteredPoints::kFanout;
  auto support = [&](std::size_t level, std::size_t i) {
    return boxSupport(a, t, c.levels[level].min[i], c.levels[level].max[i]);
  };
  // The boxes under box i of `level` (the whole top level for level = levels.size()).
  auto childrenOf = [&](std::size_t level, std::size_t i) {
    const std::size_t count = c.levels[level - 1].min.size();
    return level == c.levels.size() ? std::pair<std::size_t, std::size_t>(0, count)
                                    : std::pair(i * kFanout, std::min(count, (i + 1) * kFanout));
  };

  std::size_t seed = 0;
  for (std::size_t level = c.levels.size(); level > 0; --level) {
    const auto [first, end] = childrenOf(level, seed);
    seed = first;
    double seedValue = support(level - 1, first);
    for (std::size_t i = first + 1; i < end; ++i)
      if (const double v = support(level - 1, i); v > seedValue) seed = i, seedValue = v;
  }
  double best = clusterMaximum(c, seed, a, t);

  // Depth first over ranges of sibling boxes, one range per level at most.
  struct Range {
    std::size_t level, next, end;
  };
  std::array<Range, ClusteredPoints::kMaxLevels> stack;
  std::size_t depth = 0;
  {
    const auto [first, end] = childrenOf(c.levels.size(), 0);
    stack[depth++] = {c.levels.size() - 1, first, end};
  }
  while (depth > 0) {
    Range& range = stack[depth - 1];
    if (range.next == range.end) {
      --depth;
      continue;
    }
    const std::size_t level = range.level, i = range.next++;
    if (support(level, i) <= best) continue;  // nothing under it can beat `best`
    if (level == 0) {
      if (i != seed) best = std::max(best, clusterMaximum(c, i, a, t));
    } else {
      const auto [first, end] = childrenOf(level, i);
      stack[depth++] = {level - 1, first, end};
    }
  }
  return best;
}

// The box of each run of `run` consecutive boxes [lo[i], hi[i]] (points: lo = hi).
void boxesOfRuns(const std::vector<glm::vec3>& lo, const std::vector<glm::vec3>& hi, std::size_t run,
                 std::vector<glm::vec3>& runMin, std::vector<glm::vec3>& runMax) {
  for (std::size_t first = 0; first < lo.size(); first += run) {
    const std::size_t end = std::min(lo.size(), first + run);
    glm::vec3 rlo = lo[first], rhi = hi[first];
    for (std::size_t i = first + 1; i < end; ++i) {
      rlo = glm::min(rlo, lo[i]);
      rhi = glm::max(rhi, hi[i]);
    }
    runMin.push_back(rlo);
    runMax.push_back(rhi);
  }
}

}  // namespace

ClusteredPoints clusterPoints(std::span<const glm::vec3> positions) {
  ClusteredPoints c;
  if (positions.empty()) return c;
  glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  for (const glm::vec3& p : positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::vec3 extent = glm::max(hi - lo, glm::vec3(std::numeric_limits<float>::min()));
  std::vector<std::pair<std::uint32_t, std::uint32_t>> keyed(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const glm::vec3 q = glm::clamp((positions[i] - lo) / extent, 0.0f, 1.0f) * 1023.0f;
    keyed[i] = {spreadBits(std::uint32_t(q.x)) | (spreadBits(std::uint32_t(q.y)) << 1) |
                    (spreadBits(std::uint32_t(q.z)) << 2),
                std::uint32_t(i)};
  }
  std::sort(keyed.begin(), keyed.end());  // ties by index: deterministic
  c.points.reserve(positions.size());
  for (const auto& [code, index] : keyed) c.points.push_back(positions[index]);
  c.levels.emplace_back();
  boxesOfRuns(c.points, c.points, ClusteredPoints::kClusterSize, c.levels[0].min, c.levels[0].max);
  while (c.levels.back().min.size() > ClusteredPoints::kFanout) {
    ClusteredPoints::Level above;
    boxesOfRuns(c.levels.back().min, c.levels.back().max, ClusteredPoints::kFanout, above.min, above.max);
    c.levels.push_back(std::move(above));
  }
  return c;
}

Bounds transformedPointBounds(const ClusteredPoints& clustered, const glm::dmat4& m) {
  Bounds bounds;
  if (clustered.points.empty()) return bounds;
  for (int axis = 0; axis < 3; ++axis) {
    const glm::dvec3 row(m[0][axis], m[1][axis], m[2][axis]);
    const double t = m[3][axis];
    bounds.max[axis] = exactMaximum(clustered, row, t);
    bounds.min[axis] = 0.0 - exactMaximum(clustered, -row, -t);  // 0.0 − x: no negative zero
  }
  return bounds;
}

}  // namespace pbs::detail
