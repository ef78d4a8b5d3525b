// Branch-and-bound over point clusters for exact transformed bounds: a cluster's box bounds what
// its points can reach along an axis, one real point of each cluster gives a value that is reached,
// and only clusters whose bound beats the best reached value are read point by point.
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

// max over all points of a·p + t, exactly.
double exactMaximum(const ClusteredPoints& c, const glm::dvec3& a, double t) {
  const std::size_t clusters = c.clusterMin.size();
  double reached = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < clusters; ++k)
    reached = std::max(reached, pointValue(a, t, c.points[k * ClusteredPoints::kClusterSize]));
  // The box support and the point values round differently; a small slack keeps the pruning safe.
  const double slack = 1e-9 * (std::abs(reached) + std::abs(t) + 1.0);
  double best = reached;
  for (std::size_t k = 0; k < clusters; ++k) {
    if (boxSupport(a, t, c.clusterMin[k], c.clusterMax[k]) + slack < best) continue;
    const std::size_t end = std::min(c.points.size(), (k + 1) * ClusteredPoints::kClusterSize);
    for (std::size_t i = k * ClusteredPoints::kClusterSize; i < end; ++i) best = std::max(best, pointValue(a, t, c.points[i]));
  }
  return best;
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
  for (std::size_t first = 0; first < c.points.size(); first += ClusteredPoints::kClusterSize) {
    const std::size_t end = std::min(c.points.size(), first + ClusteredPoints::kClusterSize);
    glm::vec3 clo = c.points[first], chi = c.points[first];
    for (std::size_t i = first + 1; i < end; ++i) {
      clo = glm::min(clo, c.points[i]);
      chi = glm::max(chi, c.points[i]);
    }
    c.clusterMin.push_back(clo);
    c.clusterMax.push_back(chi);
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
