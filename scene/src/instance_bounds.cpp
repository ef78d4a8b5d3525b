// Branch-and-bound over point clusters for exact transformed bounds: a cluster's (or a group's) box
// bounds what its points can reach along an axis, the points of the most promising cluster give a value
// that is reached, and only the clusters whose bound beats it are read point by point.
#include "instance_bounds.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>

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

// Largest value of a·p + t over the box [lo, hi]: each term takes the end its sign favours.
double boxSupport(const glm::dvec3& a, double t, const glm::vec3& lo, const glm::vec3& hi) {
  double s = t;
  for (int j = 0; j < 3; ++j) s += a[j] * (a[j] >= 0.0 ? double(hi[j]) : double(lo[j]));
  return s;
}

double pointValue(const glm::dvec3& a, double t, const glm::vec3& p) {
  return a.x * double(p.x) + a.y * double(p.y) + a.z * double(p.z) + t;
}

// max of a·p + t over the points of cluster k.
double clusterMaximum(const ClusteredPoints& c, std::size_t k, const glm::dvec3& a, double t) {
  double best = -std::numeric_limits<double>::infinity();
  const std::size_t end = std::min(c.points.size(), (k + 1) * ClusteredPoints::kClusterSize);
  for (std::size_t i = k * ClusteredPoints::kClusterSize; i < end; ++i) best = std::max(best, pointValue(a, t, c.points[i]));
  return best;
}

// max over all points of a·p + t, exactly. The cluster with the largest box bound in the group with the
// largest one is read first: its points nearly always hold the maximum, so the bound that follows prunes
// all but a few groups and clusters.
double exactMaximum(const ClusteredPoints& c, const glm::dvec3& a, double t) {
  const std::size_t groups = c.groupMin.size(), clusters = c.clusterMin.size();
  constexpr std::size_t kGroup = ClusteredPoints::kGroupSize;
  auto clusterSupport = [&](std::size_t k) { return boxSupport(a, t, c.clusterMin[k], c.clusterMax[k]); };
  auto groupSupport = [&](std::size_t g) { return boxSupport(a, t, c.groupMin[g], c.groupMax[g]); };
  auto clustersOf = [&](std::size_t g) { return std::pair(g * kGroup, std::min(clusters, (g + 1) * kGroup)); };

  // The first i in [first, end) with the largest value(i).
  auto argmax = [](std::size_t first, std::size_t end, const auto& value) {
    std::size_t best = first;
    double bestValue = value(first);
    for (std::size_t i = first + 1; i < end; ++i)
      if (const double v = value(i); v > bestValue) best = i, bestValue = v;
    return best;
  };
  const auto [seedFirst, seedEnd] = clustersOf(argmax(0, groups, groupSupport));
  const std::size_t seed = argmax(seedFirst, seedEnd, clusterSupport);
  double best = clusterMaximum(c, seed, a, t);
  // The box bounds and the point values round differently; a small slack keeps the pruning safe.
  const double slack = 1e-9 * (std::abs(best) + std::abs(t) + 1.0);
  for (std::size_t g = 0; g < groups; ++g) {
    if (groupSupport(g) + slack < best) continue;
    const auto [first, end] = clustersOf(g);
    for (std::size_t k = first; k < end; ++k)
      if (k != seed && clusterSupport(k) + slack >= best) best = std::max(best, clusterMaximum(c, k, a, t));
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
  boxesOfRuns(c.points, c.points, ClusteredPoints::kClusterSize, c.clusterMin, c.clusterMax);
  boxesOfRuns(c.clusterMin, c.clusterMax, ClusteredPoints::kGroupSize, c.groupMin, c.groupMax);
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
