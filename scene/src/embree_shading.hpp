// Turning one ray hit into G-buffer values with the rasterizer's conventions (depth, colour,
// position, normal, ids), and the cleared values of a miss.
#pragma once

#include "pbs/raster/camera.hpp"
#include "pbs/raster/framebuffer.hpp"
#include "pbs/raster/triangles.hpp"
#include "pbs/scene/scene.hpp"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <span>

namespace pbs {

// What shading needs of one instance (a node carrying a mesh), prepared once at build time. Small:
// scenes hold millions of instances, so the transform stays in the Hierarchy.
struct ShadedInstance {
  const Mesh* mesh = nullptr;
  std::span<const SurfaceMaterial> materials;  // indexed by MeshPart::material
  const glm::dmat4* worldFromObject = nullptr;
  std::uint32_t node = 0;
  std::uint32_t meshIndex = 0;
};

// The view a render shades for: the camera with its matrices multiplied out once.
struct ShadingView {
  explicit ShadingView(const Camera& c)
      : camera(&c), clipFromWorld(c.clipFromWorld()), windowFromWorld(windowFromClipMatrix(c) * clipFromWorld) {}
  const Camera* camera;
  glm::dmat4 clipFromWorld;
  glm::dmat4 windowFromWorld;  // homogeneous window coordinates (x·w, y·w, ·, w): windowFromClipMatrix
};

// The matrices of the instance shaded last, each made the first time a hit on it needs it: for normals
// (the inverse-transpose) and for texture footprints (object to homogeneous window coordinates). A
// packet's hits mostly share an instance, and instances are too many to store them each. One per thread.
class InstanceMatrices {
 public:
  explicit InstanceMatrices(const ShadingView& view) : view_(view) {}

  const glm::dmat3& normalFromObject(const ShadedInstance& instance) {
    if (&instance != normalOf_) {
      normal_ = glm::transpose(glm::inverse(glm::dmat3(*instance.worldFromObject)));
      normalOf_ = &instance;
    }
    return normal_;
  }
  const glm::dmat4& windowFromObject(const ShadedInstance& instance) {
    if (&instance != windowOf_) {
      window_ = view_.windowFromWorld * *instance.worldFromObject;
      windowOf_ = &instance;
    }
    return window_;
  }

 private:
  const ShadingView& view_;
  const ShadedInstance* normalOf_ = nullptr;
  const ShadedInstance* windowOf_ = nullptr;
  glm::dmat3 normal_{1.0};
  glm::dmat4 window_{1.0};
};

// Starts fetching what shadeHit reads first of `triangle`, its three indices.
inline void prefetchHitIndices(const ShadedInstance& instance, std::uint32_t triangle) {
  __builtin_prefetch(instance.mesh->indices.data() + std::size_t(triangle) * 3);
}

// Writes pixel `pixel` of every channel the framebuffer has for a hit on `triangle` of the
// instance's mesh at barycentrics (u, v) (the point (1−u−v)·p0 + u·p1 + v·p2, Embree's convention).
void shadeHit(const ShadingView& view, const ShadedInstance& instance, InstanceMatrices& matrices,
              std::uint32_t triangle, float u, float v, Framebuffer& framebuffer, std::size_t pixel);

// Misses: clears depth and ids at the `count` pixels from `first` on (one row's run). Colour, position and normal
// keep what they held, as the rasterizer's depth-only clear leaves them: they mean something only where depth says
// a pixel is covered, and nothing reads them elsewhere (in a frame of a distant scene, most pixels).
void clearMissedPixels(Framebuffer& framebuffer, std::size_t first, std::size_t count);

}  // namespace pbs
