// Axis-aligned bounding boxes in double precision, so scenes far from the origin keep their digits.
#pragma once

#include <glm/glm.hpp>

#include <limits>

namespace pbs {

struct Bounds {
  glm::dvec3 min{std::numeric_limits<double>::infinity()};
  glm::dvec3 max{-std::numeric_limits<double>::infinity()};

  bool empty() const { return !(min.x <= max.x && min.y <= max.y && min.z <= max.z); }
  glm::dvec3 center() const { return (min + max) * 0.5; }
  glm::dvec3 size() const { return empty() ? glm::dvec3(0.0) : max - min; }

  void extend(const glm::dvec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  void extend(const Bounds& other) {
    if (other.empty()) return;
    extend(other.min);
    extend(other.max);
  }
};

// The box around the eight transformed corners: conservative (not tight) under rotation.
inline Bounds transformCorners(const Bounds& box, const glm::dmat4& m) {
  Bounds result;
  if (box.empty()) return result;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 p{(corner & 1) ? box.max.x : box.min.x, (corner & 2) ? box.max.y : box.min.y,
                       (corner & 4) ? box.max.z : box.min.z};
    result.extend(glm::dvec3(m * glm::dvec4(p, 1.0)));
  }
  return result;
}

}  // namespace pbs
