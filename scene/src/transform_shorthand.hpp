// Shorthand for the placements the procedural generators compose: moves, quarter and free turns
// about the axes, and scales, all in double precision like Node::local.
#pragma once

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace pbs {

inline glm::dmat4 at(double x, double y, double z) { return glm::translate(glm::dmat4(1.0), glm::dvec3(x, y, z)); }
inline glm::dmat4 turnX(double radians) { return glm::rotate(glm::dmat4(1.0), radians, glm::dvec3(1, 0, 0)); }
inline glm::dmat4 turnY(double radians) { return glm::rotate(glm::dmat4(1.0), radians, glm::dvec3(0, 1, 0)); }
inline glm::dmat4 turnZ(double radians) { return glm::rotate(glm::dmat4(1.0), radians, glm::dvec3(0, 0, 1)); }
inline glm::dmat4 scaled(double x, double y, double z) { return glm::scale(glm::dmat4(1.0), glm::dvec3(x, y, z)); }

// Procedural parts rise along +Y; these lay them along +X or +Z.
inline glm::dmat4 alongX() { return turnZ(-glm::half_pi<double>()); }
inline glm::dmat4 alongZ() { return turnX(glm::half_pi<double>()); }

}  // namespace pbs
