// The rays of windowRay (camera.hpp) for many pixels of one camera, each with the part of it between
// the near and far planes: the same unprojection, with its matrix inverses computed once per camera.
#pragma once

#include "pbs/raster/camera.hpp"

#include <cmath>

namespace pbs {

struct RaySegment {
  Ray ray;       // as windowRay(camera, xw, yw) gives it, up to rounding
  double tNear;  // the ray meets the near plane here …
  double tFar;   // … and the far plane here
};

class WindowRays {
 public:
  explicit WindowRays(const Camera& camera);

  // The pixel position's points on the near and far planes are the unprojections of NDC z = −1
  // and +1, so the visible stretch of the ray comes with the ray itself.
  // Written with reciprocals rather than divisions: this runs once per pixel.
  RaySegment at(double xw, double yw) const {
    const double xn = xw * xScale_ - 1.0;
    const double yn = 1.0 - yw * yScale_;
    const glm::dvec4 onPlane = worldFromClip_[0] * xn + worldFromClip_[1] * yn;
    const glm::dvec4 nearH = onPlane + nearColumn_;
    const glm::dvec4 farH = onPlane + farColumn_;
    const glm::dvec3 onNear = glm::dvec3(nearH) * (1.0 / nearH.w);
    const glm::dvec3 onFar = glm::dvec3(farH) * (1.0 / farH.w);
    // An orthographic ray starts on the near plane; a perspective one at the eye, toward it.
    const glm::dvec3 origin = orthographic_ ? onNear : eye_;
    const glm::dvec3 toFar = onFar - origin;
    const double tFar = std::sqrt(glm::dot(toFar, toFar));
    if (orthographic_) return {{origin, toFar * (1.0 / tFar)}, 0.0, tFar};
    const glm::dvec3 toNear = onNear - origin;
    const double tNear = std::sqrt(glm::dot(toNear, toNear));
    return {{origin, toNear * (1.0 / tNear)}, tNear, tFar};
  }

 private:
  double xScale_;  // 2 / width
  double yScale_;  // 2 / height
  bool orthographic_;
  glm::dmat4 worldFromClip_;
  glm::dvec4 nearColumn_;  // worldFromClip · (0, 0, −1, 1)
  glm::dvec4 farColumn_;   // worldFromClip · (0, 0, +1, 1)
  glm::dvec3 eye_;
};

}  // namespace pbs
