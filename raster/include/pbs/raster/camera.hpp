// Cameras: view and projection matrices plus a viewport, and the exact mapping from world space to
// window coordinates that the rasterizer, the reference rasterizer and the Embree ray caster share.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>

namespace pbs {

// Conventions (OpenGL-style clip space, image-style window):
// - view: eye-from-world, right-handed, the camera looks down −Z.
// - projection: clip-from-eye; the visible volume is −w ≤ x, y, z ≤ w.
// - window: x_w = (x/w + 1)·W/2, y_w = (1 − y/w)·H/2 (row 0 is the top row), depth = (z/w + 1)/2.
// - pixel (px, py) covers [px, px+1) × [py, py+1); its sample is the centre (px + 0.5, py + 0.5).
// All of it is evaluated in double precision.
struct Camera {
  glm::dmat4 view{1.0};
  glm::dmat4 projection{1.0};
  std::uint32_t width = 1;   // 1 … 16384
  std::uint32_t height = 1;  // 1 … 16384
  // Pixels between neighbouring samples of the image this camera draws (1/√n for n samples per pixel,
  // subpixelCamera): each sample's texture footprint is that much of a pixel (TextureFootprint).
  double sampleSpacing = 1.0;
  // The most probes a minified texture sample takes along a footprint longer than wide (anisotropic
  // filtering, sampleTexture). Measured on the default scene's approach with one ray a pixel: 4 takes FLIP
  // from 0.0659–0.0327 to 0.0615–0.0238 on its near frames, and 8 with probes rounded up no further than
  // 0.0601–0.0232; 1 is OpenGL's isotropic rule, which the capture views keep (boxViewCamera); 0 samples
  // level 0 alone, unfiltered (TextureFootprint; `pbs render --texture-filter none`).
  std::uint32_t textureProbes = 4;

  bool isOrthographic() const { return projection[2][3] == 0.0; }
  glm::dmat4 clipFromWorld() const { return projection * view; }
};

// glm::ortho-style volume in eye space: [left, right] × [bottom, top], near/far distances along −Z.
Camera orthographicCamera(const glm::dmat4& view, double left, double right, double bottom, double top, double near,
                          double far, std::uint32_t width, std::uint32_t height);

// Vertical field of view in radians; the aspect ratio follows the viewport.
Camera perspectiveCamera(const glm::dmat4& view, double fovY, double near, double far, std::uint32_t width,
                         std::uint32_t height);

// Whether a matrix into clip space keeps w ≡ 1 (its w row is (0, 0, 0, 1): an orthographic
// projection of affine transforms), so that the division by w can be skipped exactly.
inline bool keepsUnitW(const glm::dmat4& m) {
  return m[0][3] == 0.0 && m[1][3] == 0.0 && m[2][3] == 0.0 && m[3][3] == 1.0;
}

// Window position (x_w, y_w) and depth of a clip-space point (w ≠ 0).
glm::dvec3 windowFromClip(const Camera& camera, const glm::dvec4& clip);

// The same as a matrix for code that projects many points: rows (W/2·(x + w), H/2·(w − y), (z + w)/2, w),
// which divided by w are the window x, y and depth (equal to windowFromClip up to rounding).
glm::dmat4 windowFromClipMatrix(const Camera& camera);

// The world-space ray through window position (x_w, y_w): for a perspective camera from the eye,
// for an orthographic one from the near plane along the view direction. `direction` is unit length;
// a point at ray parameter t has world position origin + t·direction.
struct Ray {
  glm::dvec3 origin;
  glm::dvec3 direction;
};
Ray windowRay(const Camera& camera, double xw, double yw);

// Window depth (as stored in the depth channel) of a world-space point.
double windowDepth(const Camera& camera, const glm::dvec3& world);

}  // namespace pbs
