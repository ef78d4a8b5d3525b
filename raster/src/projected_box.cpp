// Projected box silhouettes: corners to window space, convex hull (monotone chain), shoelace area.
#include "pbs/raster/projected_box.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace pbs {
namespace {

double cross(const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

}  // namespace

double projectedBoxPixels(const Camera& camera, const Bounds& box) {
  if (box.empty()) return 0.0;
  const glm::dmat4 clipFromWorld = camera.clipFromWorld();
  const glm::dvec3 half = box.size() * 0.5;
  const glm::dvec3 center = box.center();
  std::array<glm::dvec2, 8> points;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 offset{(corner & 1) ? half.x : -half.x, (corner & 2) ? half.y : -half.y,
                            (corner & 4) ? half.z : -half.z};
    glm::dvec2& p = points[std::size_t(corner)];
    if (camera.isOrthographic()) {
      // w = 1, so window offsets are clip offsets scaled by half the viewport.
      const glm::dvec4 clip = clipFromWorld * glm::dvec4(offset, 0.0);
      p = {clip.x * camera.width * 0.5, -clip.y * camera.height * 0.5};
    } else {
      const glm::dvec4 clip = clipFromWorld * glm::dvec4(center + offset, 1.0);
      if (!(clip.w > 0.0)) return std::numeric_limits<double>::infinity();
      p = glm::dvec2(windowFromClip(camera, clip));
    }
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
