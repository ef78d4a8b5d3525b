// Projected box silhouettes: corners to window space, convex hull (monotone chain), shoelace area.
#include "capture_coverage.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace pbs {
namespace {

double cross(const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

}  // namespace

double projectedBoxPixels(const Camera& orthographic, const Bounds& box) {
  if (box.empty()) return 0.0;
  const glm::dmat4 clipFromWorld = orthographic.clipFromWorld();
  const glm::dvec3 half = box.size() * 0.5;
  std::array<glm::dvec2, 8> points;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 offset{(corner & 1) ? half.x : -half.x, (corner & 2) ? half.y : -half.y,
                            (corner & 4) ? half.z : -half.z};
    // w = 1 for an orthographic camera, so window offsets are clip offsets scaled by half the viewport.
    const glm::dvec4 clip = clipFromWorld * glm::dvec4(offset, 0.0);
    points[std::size_t(corner)] = {clip.x * orthographic.width * 0.5, -clip.y * orthographic.height * 0.5};
  }
  std::sort(points.begin(), points.end(),
            [](const glm::dvec2& a, const glm::dvec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  // Andrew's monotone chain: lower hull then upper hull, counter-clockwise.
  std::array<glm::dvec2, 16> hull;
  std::size_t size = 0;
  for (int pass = 0; pass < 2; ++pass) {
    const std::size_t start = size;
    for (std::size_t k = 0; k < points.size(); ++k) {
      const glm::dvec2& p = pass == 0 ? points[k] : points[points.size() - 1 - k];
      while (size >= start + 2 && cross(hull[size - 2], hull[size - 1], p) <= 0.0) --size;
      hull[size++] = p;
    }
    --size;  // the last point starts the other chain
  }
  double twiceArea = 0.0;
  for (std::size_t i = 0; i < size; ++i) {
    const glm::dvec2& a = hull[i];
    const glm::dvec2& b = hull[(i + 1) % size];
    twiceArea += a.x * b.y - b.x * a.y;
  }
  return std::abs(twiceArea) * 0.5;
}

}  // namespace pbs
