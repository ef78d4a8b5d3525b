// orbitCamera: spherical coordinates to a look-at view and a perspective projection.
#include "pbs/raster/orbit_camera.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace pbs {

glm::dvec3 orbitDirection(const Orbit& orbit) {
  const double azimuth = glm::radians(orbit.azimuthDegrees);
  const double elevation = glm::radians(std::clamp(orbit.elevationDegrees, -89.9, 89.9));
  return {std::cos(elevation) * std::cos(azimuth), std::sin(elevation), std::cos(elevation) * std::sin(azimuth)};
}

Camera orbitCamera(const glm::dvec3& center, double radius, const Orbit& orbit, std::uint32_t width,
                   std::uint32_t height) {
  return orbitCamera(center, center, radius, orbit, width, height);
}

Camera orbitCamera(const glm::dvec3& target, const glm::dvec3& center, double radius, const Orbit& orbit,
                   std::uint32_t width, std::uint32_t height) {
  if (!(radius > 0.0)) radius = 1.0;
  const glm::dvec3 direction = orbitDirection(orbit);
  const double distance = std::max(orbit.distance, 1e-6) * radius;
  const glm::dvec3 eye = target + direction * distance;
  const glm::dmat4 view = glm::lookAt(eye, target, glm::dvec3(0.0, 1.0, 0.0));
  // A sphere around the target that holds the scene's: the scene's own when the target is its centre.
  const double reach = radius + glm::length(target - center);
  const double near = std::max(distance - reach, radius * 1e-4);
  const double far = distance + reach;
  return perspectiveCamera(view, glm::radians(kOrbitFovYDegrees), near, far, width, height);
}

}  // namespace pbs
