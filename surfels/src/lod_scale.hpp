// How large a node's frame and a pixel are at a node, for the LOD traversals (threshold and budget).
#pragma once

#include "pbs/raster/camera.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

namespace pbs::lod {

// World size of one pixel at `point`: constant for orthographic cameras, growing with the eye-space
// depth for perspective ones (row 1 of the projection scales eye y to clip y).
inline double worldPixelAt(const Camera& camera, const glm::dvec3& point) {
  const double perUnitDepth = 2.0 / (camera.projection[1][1] * camera.height);
  if (camera.isOrthographic()) return perUnitDepth;
  const double depth = -(camera.view * glm::dvec4(point, 1.0)).z;
  return perUnitDepth * std::max(depth, 0.0);
}

// The node frame's scale as the cube root of the volume change (mirroring ignored).
inline double frameScale(const glm::dmat4& world) { return std::cbrt(std::abs(glm::determinant(glm::dmat3(world)))); }

}  // namespace pbs::lod
