// Cameras on an orbit around a bounding sphere: the views of `pbs render --orbit` and of `pbs eval`.
#pragma once

#include "pbs/raster/camera.hpp"

#include <glm/glm.hpp>

#include <cstdint>

namespace pbs {

struct Orbit {
  double azimuthDegrees = 30.0;    // around +Y (glTF's up), from +X toward +Z
  double elevationDegrees = 20.0;  // above the XZ plane
  double distance = 2.5;           // eye to centre, in bounding radii
};

inline constexpr double kOrbitFovYDegrees = 45.0;

// The unit direction from the centre toward the orbit's eye: (cos el·cos az, sin el, cos el·sin az),
// the elevation clamped to ±89.9° (a look-at needs up ≠ view).
glm::dvec3 orbitDirection(const Orbit& orbit);

// A perspective camera at `orbit` around the sphere (centre, radius) looking at its centre, +Y up,
// vertical field of view kOrbitFovYDegrees. Near and far enclose the sphere (near at least
// radius × 1e-4 when the eye is inside it). A radius ≤ 0 is treated as 1.
Camera orbitCamera(const glm::dvec3& center, double radius, const Orbit& orbit, std::uint32_t width,
                   std::uint32_t height);

// The same orbit around `target` instead of the centre (a viewer's camera that has flown away from it):
// distance in the sphere's radii, near and far enclosing the sphere from the eye. With the target at the
// centre it is the camera above, bit for bit.
Camera orbitCamera(const glm::dvec3& target, const glm::dvec3& center, double radius, const Orbit& orbit,
                   std::uint32_t width, std::uint32_t height);

}  // namespace pbs
