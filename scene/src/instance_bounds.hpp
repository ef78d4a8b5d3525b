// Exact world bounds of mesh instances without transforming every vertex of every instance.
#pragma once

#include "pbs/raster/bounds.hpp"

#include <glm/glm.hpp>

#include <span>
#include <vector>

namespace pbs::detail {

// A mesh's vertices reordered along a Morton curve and cut into small clusters with their boxes, the
// clusters in turn into groups with theirs, built once per mesh and shared by all its instances. The
// groups let an instance skip most clusters without looking at each: a city of 100,000 instances of
// meshes of 50,000 vertices would otherwise test every cluster box of every instance.
struct ClusteredPoints {
  static constexpr std::size_t kClusterSize = 64;
  static constexpr std::size_t kGroupSize = 16;  // clusters per group
  std::vector<glm::vec3> points;      // the vertices, Morton-ordered
  std::vector<glm::vec3> clusterMin;  // per cluster of kClusterSize consecutive points
  std::vector<glm::vec3> clusterMax;
  std::vector<glm::vec3> groupMin;    // per group of kGroupSize consecutive clusters
  std::vector<glm::vec3> groupMax;
};

ClusteredPoints clusterPoints(std::span<const glm::vec3> positions);

// The tight box of every point through `transform`, exactly as transforming all of them would give
// (each axis' extreme is the maximum of exact dot products), but only clusters whose transformed
// box could hold an extreme are visited: a few per axis instead of all of them.
Bounds transformedPointBounds(const ClusteredPoints& clustered, const glm::dmat4& transform);

}  // namespace pbs::detail
