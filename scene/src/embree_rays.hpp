// The rays of windowRay (camera.hpp) for many pixels of one camera, each with the part of it between
// the near and far planes: the same unprojection, with its matrix inverses computed once per camera.
#pragma once

#include "pbs/raster/camera.hpp"

#include <cmath>

namespace pbs {

// One pixel's ray as windowRay (camera.hpp) gives it, up to rounding, with the part of it between the near and far
// planes; in plain numbers, so that a loop making many runs in vector lanes.
struct RaySegment {
  double originX, originY, originZ;
  double directionX, directionY, directionZ;  // unit length
  double tNear;                               // the ray meets the near plane here …
  double tFar;                                // … and the far plane here
};

class WindowRays {
 public:
  explicit WindowRays(const Camera& camera);

  bool orthographic() const { return orthographic_; }

  // The ray through window position (xw, yw) of a camera that is orthographic or not as `Orthographic` says (the
  // camera's own, orthographic()). The position's points on the near and far planes are the unprojections of NDC
  // z = −1 and +1, so the visible stretch of the ray comes with the ray itself. Written with reciprocals rather
  // than divisions: this runs once per pixel.
  template <bool Orthographic>
  [[gnu::always_inline]] RaySegment at(double xw, double yw) const {
    RaySegment ray;
    const double xn = xw * xScale_ - 1.0;
    const double yn = 1.0 - yw * yScale_;
    const glm::dmat4& m = worldFromClip_;
    const auto unproject = [&](const glm::dvec4& column, double& x, double& y, double& z) {
      const double inverseW = 1.0 / (m[0].w * xn + m[1].w * yn + column.w);
      x = (m[0].x * xn + m[1].x * yn + column.x) * inverseW;
      y = (m[0].y * xn + m[1].y * yn + column.y) * inverseW;
      z = (m[0].z * xn + m[1].z * yn + column.z) * inverseW;
    };
    double nearX, nearY, nearZ, farX, farY, farZ;
    unproject(nearColumn_, nearX, nearY, nearZ);
    unproject(farColumn_, farX, farY, farZ);
    // An orthographic ray starts on the near plane and runs toward the far one; a perspective one starts at the
    // eye and runs toward the near plane.
    ray.originX = Orthographic ? nearX : eye_.x;
    ray.originY = Orthographic ? nearY : eye_.y;
    ray.originZ = Orthographic ? nearZ : eye_.z;
    const double toFarX = farX - ray.originX, toFarY = farY - ray.originY, toFarZ = farZ - ray.originZ;
    ray.tFar = std::sqrt(toFarX * toFarX + toFarY * toFarY + toFarZ * toFarZ);
    if constexpr (Orthographic) {
      ray.tNear = 0.0;
      const double inverseLength = 1.0 / ray.tFar;
      ray.directionX = toFarX * inverseLength;
      ray.directionY = toFarY * inverseLength;
      ray.directionZ = toFarZ * inverseLength;
    } else {
      const double toNearX = nearX - ray.originX, toNearY = nearY - ray.originY, toNearZ = nearZ - ray.originZ;
      ray.tNear = std::sqrt(toNearX * toNearX + toNearY * toNearY + toNearZ * toNearZ);
      const double inverseLength = 1.0 / ray.tNear;
      ray.directionX = toNearX * inverseLength;
      ray.directionY = toNearY * inverseLength;
      ray.directionZ = toNearZ * inverseLength;
    }
    return ray;
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
