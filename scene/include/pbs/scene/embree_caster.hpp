// Ray casting a scene with Embree 3 into the rasterizer's G-buffer: the reference that checks the
// rasterizer's visibility, and a peer it is benchmarked against.
#pragma once

#include "pbs/raster/camera.hpp"
#include "pbs/raster/framebuffer.hpp"
#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/scene.hpp"

#include <cstdint>
#include <memory>
#include <span>

namespace pbs {

// Build once, cast many cameras. One bottom-level BVH per mesh that some node uses, shared by all
// its instances; a top-level BVH of the instances (node world transforms).
//
// Embree works in single precision, so its world is translated by origin() (the centre of the
// scene's bounds): instance transforms and ray origins are made relative to it in double before
// rounding, and far-from-origin scenes keep their digits. Every result is in world space.
class EmbreeScene {
 public:
  // Builds the BVHs (this is the whole build cost; time it here). `scene` and `hierarchy` (from
  // analyzeHierarchy(scene)) must outlive this object and stay unchanged: render reads meshes,
  // materials, textures and world transforms from them rather than keep copies. Embree errors throw
  // std::runtime_error.
  EmbreeScene(const Scene& scene, const Hierarchy& hierarchy);
  // The same restricted to the mesh instances of `nodes` (e.g. subtreeNodes of a node being
  // captured); origin() is then the centre of those nodes' world bounds.
  EmbreeScene(const Scene& scene, const Hierarchy& hierarchy, std::span<const std::uint32_t> nodes);
  ~EmbreeScene();
  EmbreeScene(EmbreeScene&&) noexcept;  // a moved-from EmbreeScene may only be destroyed or assigned to
  EmbreeScene& operator=(EmbreeScene&&) noexcept;

  // Writes every pixel, with the rasterizer's conventions: one ray per pixel centre (windowRay); the
  // nearest hit inside the camera's near/far range gives depth (windowDepth of the hit point), colour
  // (material base colour × bilinear texture, RGBA8), position (hit − positionOrigin), normal
  // (interpolated vertex normal through the inverse-transpose, unit length) and ids (node, mesh,
  // triangle), in the channels `framebuffer` has; a miss clears depth and ids and leaves colour,
  // position and normal as they were (as the rasterizer's depth-only clear does: read them only where
  // depth says a pixel is covered). Rays are cast only where the instances' boxes show; every other pixel
  // is cleared as a miss, the same bits a ray there would give, at a fraction of its cost.
  // Faces are never culled. Runs on the current TBB arena, 16-ray packets of 4×4 pixels; the
  // result does not depend on the thread count. Throws std::invalid_argument when the framebuffer
  // is not the camera's size.
  void render(const Camera& camera, Framebuffer& framebuffer) const;

  const glm::dvec3& origin() const;

  // Bytes Embree holds for this scene's BVHs and its copies of the vertices, now and at most so far (the
  // build's peak), as Embree's memory monitor reports them; with the node casters that share its
  // device (EmbreeNodeCaster), theirs too.
  std::uint64_t bytes() const;
  std::uint64_t peakBytes() const;

 private:
  friend class EmbreeNodeCaster;  // shares the mesh BVHs
  struct Impl;
  std::unique_ptr<Impl> impl_;  // holds the Embree objects, so no Embree header leaks out of here
};

// What EmbreeScene(scene, hierarchy) will allocate at most, from its meshes' triangles and vertices and
// its instances, calibrated on Embree 3's robust triangle BVHs (docs/performance.md): lets a command
// refuse a build that would not fit before starting it. Takes a scene opened without its mesh arrays too
// (Mesh::vertexCount), so the refusal can come before the scene is read.
std::uint64_t embreeMemoryEstimate(const Scene& scene, const Hierarchy& hierarchy);

}  // namespace pbs
