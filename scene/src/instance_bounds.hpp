// Exact world bounds of mesh instances without transforming every vertex of every instance.
#pragma once

#include "pbs/raster/bounds.hpp"

#include <glm/glm.hpp>

#include <array>
#include <span>
#include <vector>

namespace pbs::detail {

// A mesh's vertices reordered along a Morton curve and cut into small clusters, with a tree of boxes
// over them: level 0 holds each cluster's box, each level above the box of every kFanout consecutive
// boxes below it, up to a top level of at most kFanout boxes. Built once per mesh and shared by all its
// instances. The tree lets small clusters (few points read per cluster that may hold an extreme) cost
// box tests that grow with the logarithm of the mesh's size, not with it.
struct ClusteredPoints {
  static constexpr std::size_t kClusterSize = 16;
  static constexpr std::size_t kFanout = 16;    // boxes per box of the level above
  static constexpr std::size_t kMaxLevels = 8;  // 16 × 16^7 points: all a 32-bit index can reach
  // Coordinates stored per axis (x of every point, then y, then z), so that the values of a run of
  // points or boxes are computed in vector registers.
  using Coordinates = std::array<std::vector<float>, 3>;
  Coordinates points;  // the vertices, Morton-ordered
  struct Level {
    Coordinates min, max;
    std::size_t size() const { return min[0].size(); }
  };
  std::vector<Level> levels;  // [0]: per cluster of kClusterSize consecutive points; back(): the top
};

ClusteredPoints clusterPoints(std::span<const glm::vec3> positions);

// The tight box of every point through `transform`, exactly as transforming all of them would give
// (each axis' extreme is the maximum of exact dot products), but only clusters whose transformed
// box could hold an extreme are visited: a few per axis instead of all of them.
Bounds transformedPointBounds(const ClusteredPoints& clustered, const glm::dmat4& transform);

}  // namespace pbs::detail
