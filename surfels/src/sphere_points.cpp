// Uniform seeded points on the unit sphere.
#include "pbs/surfels/sphere_points.hpp"

#include "pbs/raster/seeded_random.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pbs {

std::vector<glm::vec3> uniformSpherePoints(std::uint64_t count, std::uint64_t seed) {
  SeededRandom random(seed);
  std::vector<glm::vec3> points(count);
  for (glm::vec3& p : points) {
    const double z = 2.0 * random.unit() - 1.0;
    const double phi = 2.0 * std::numbers::pi * random.unit();
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    p = glm::vec3(glm::dvec3(r * std::cos(phi), r * std::sin(phi), z));
  }
  return points;
}

}  // namespace pbs
