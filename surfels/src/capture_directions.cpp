// The capture view directions: the paper's eight box diagonals, or a spherical Fibonacci set.
#include "pbs/raster/box_view.hpp"
#include "pbs/surfels/capture.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace pbs {

std::vector<glm::dvec3> captureDirections(std::uint32_t count) {
  if (count == 0) throw std::invalid_argument("captureDirections: at least one direction is needed");
  if (count == 8) return boxCornerDirections();
  // Equal-area bands in z, each point turned by the golden angle: near-uniform for any count and a
  // pure function of it.
  const double goldenAngle = std::numbers::pi * (3.0 - std::sqrt(5.0));
  std::vector<glm::dvec3> directions;
  directions.reserve(count);
  for (std::uint32_t i = 0; i < count; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / count;
    const double radius = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = goldenAngle * i;
    directions.emplace_back(radius * std::cos(phi), radius * std::sin(phi), z);
  }
  return directions;
}

}  // namespace pbs
