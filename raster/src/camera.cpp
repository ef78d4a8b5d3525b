// Camera construction and the world ↔ window mapping of camera.hpp, in double precision.
#include "pbs/raster/camera.hpp"

#include <cmath>

namespace pbs {

Camera orthographicCamera(const glm::dmat4& view, double left, double right, double bottom, double top, double near,
                          double far, std::uint32_t width, std::uint32_t height) {
  // Written out rather than glm::ortho so GLM's clip-space configuration macros cannot change it.
  glm::dmat4 projection(0.0);
  projection[0][0] = 2.0 / (right - left);
  projection[1][1] = 2.0 / (top - bottom);
  projection[2][2] = -2.0 / (far - near);
  projection[3][0] = -(right + left) / (right - left);
  projection[3][1] = -(top + bottom) / (top - bottom);
  projection[3][2] = -(far + near) / (far - near);
  projection[3][3] = 1.0;
  return Camera{view, projection, width, height};
}

Camera perspectiveCamera(const glm::dmat4& view, double fovY, double near, double far, std::uint32_t width,
                         std::uint32_t height) {
  const double aspect = double(width) / double(height);
  const double f = 1.0 / std::tan(fovY / 2.0);
  glm::dmat4 projection(0.0);
  projection[0][0] = f / aspect;
  projection[1][1] = f;
  projection[2][2] = -(far + near) / (far - near);
  projection[2][3] = -1.0;
  projection[3][2] = -2.0 * far * near / (far - near);
  return Camera{view, projection, width, height};
}

glm::dmat4 windowFromClipMatrix(const Camera& camera) {
  glm::dmat4 m(0.0);
  m[0][0] = camera.width / 2.0;
  m[1][1] = -(camera.height / 2.0);
  m[2][2] = 0.5;
  m[3] = glm::dvec4(camera.width / 2.0, camera.height / 2.0, 0.5, 1.0);
  return m;
}

glm::dvec3 windowFromClip(const Camera& camera, const glm::dvec4& clip) {
  // Orthographic clip positions have w = 1 exactly, where the division changes nothing: skip it.
  const glm::dvec3 ndc = clip.w == 1.0 ? glm::dvec3(clip) : glm::dvec3(clip) / clip.w;
  return {(ndc.x + 1.0) * camera.width / 2.0, (1.0 - ndc.y) * camera.height / 2.0, (ndc.z + 1.0) / 2.0};
}

Ray windowRay(const Camera& camera, double xw, double yw) {
  const glm::dmat4 worldFromClip = glm::inverse(camera.clipFromWorld());
  const double xn = 2.0 * xw / camera.width - 1.0;
  const double yn = 1.0 - 2.0 * yw / camera.height;
  const auto unproject = [&](double zn) {
    const glm::dvec4 p = worldFromClip * glm::dvec4(xn, yn, zn, 1.0);
    return glm::dvec3(p) / p.w;
  };
  const glm::dvec3 onNear = unproject(-1.0);
  if (camera.isOrthographic()) return {onNear, glm::normalize(unproject(1.0) - onNear)};
  const glm::dvec3 eye = glm::dvec3(glm::inverse(camera.view)[3]);
  return {eye, glm::normalize(onNear - eye)};
}

double windowDepth(const Camera& camera, const glm::dvec3& world) {
  const glm::dvec4 clip = camera.clipFromWorld() * glm::dvec4(world, 1.0);
  return (clip.z / clip.w + 1.0) / 2.0;
}

}  // namespace pbs
