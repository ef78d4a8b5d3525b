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

// The view a render shades for: the camera with its matrix multiplied out once.
struct ShadingView {
  const Camera* camera = nullptr;
  glm::dmat4 clipFromWorld{1.0};
};

// The normal matrix (inverse-transpose) of the instance shaded last: a packet's hits mostly share an
// instance, and instances are too many to store one each. One per thread.
class NormalMatrices {
 public:
  const glm::dmat3& of(const ShadedInstance& instance) {
    if (&instance != last_) {
      matrix_ = glm::transpose(glm::inverse(glm::dmat3(*instance.worldFromObject)));
      last_ = &instance;
    }
    return matrix_;
  }

 private:
  const ShadedInstance* last_ = nullptr;
  glm::dmat3 matrix_{1.0};
};

// Writes pixel `pixel` of every channel the framebuffer has for a hit on `triangle` of the
// instance's mesh at barycentrics (u, v) (the point (1−u−v)·p0 + u·p1 + v·p2, Embree's convention).
void shadeHit(const ShadingView& view, const ShadedInstance& instance, NormalMatrices& normals, std::uint32_t triangle,
              float u, float v, Framebuffer& framebuffer, std::size_t pixel);

// A miss: clears depth and ids at pixel `pixel`. Colour, position and normal keep what they held, as
// the rasterizer's depth-only clear leaves them: they mean something only where depth says a pixel is
// covered, and nothing reads them elsewhere (in a frame of a distant scene, most pixels).
void clearMissedPixel(Framebuffer& framebuffer, std::size_t pixel);

}  // namespace pbs
