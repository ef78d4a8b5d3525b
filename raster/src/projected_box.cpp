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

double projectedBoxPixels(const Camera& camera, const Bounds& box) { return BoxProjection(camera).pixels(box); }

bool outsideClipVolume(const Camera& camera, const Bounds& box) { return BoxProjection(camera).outside(box); }

double BoxProjection::pixels(const Bounds& box) const {
  if (box.empty()) return 0.0;
  const Camera& camera = camera_;
  const glm::dmat4& clipFromWorld = clipFromWorld_;
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

bool BoxProjection::outside(const Bounds& box) const {
  if (box.empty()) return true;
  // Signed distances to the six planes −w ≤ x, y, z ≤ w; outside one plane with all eight corners
  // means outside the volume (the converse does not hold, which only makes the test conservative).
  std::array<bool, 6> allOutside{true, true, true, true, true, true};
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 p{(corner & 1) ? box.max.x : box.min.x, (corner & 2) ? box.max.y : box.min.y,
                       (corner & 4) ? box.max.z : box.min.z};
    const glm::dvec4 c = clipFromWorld_ * glm::dvec4(p, 1.0);
    const std::array<double, 6> distance{c.w + c.x, c.w - c.x, c.w + c.y, c.w - c.y, c.w + c.z, c.w - c.z};
    for (int plane = 0; plane < 6; ++plane) allOutside[plane] = allOutside[plane] && distance[plane] < 0.0;
  }
  return std::any_of(allOutside.begin(), allOutside.end(), [](bool outside) { return outside; });
}

}  // namespace pbs
