// Ray casting a different set of mesh instances each frame (the LOD renderer's geometry nodes) without
// a BVH over the whole scene: a mesh's BVH is built the first time a frame needs it, then kept.
#pragma once

#include "pbs/raster/camera.hpp"
#include "pbs/raster/framebuffer.hpp"
#include "pbs/scene/embree_caster.hpp"
#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/scene.hpp"

#include <cstdint>
#include <memory>
#include <span>

namespace pbs {

// What one render built: the mesh BVHs it needed and did not have yet.
struct EmbreeBuilds {
  std::uint32_t meshes = 0;
  std::uint64_t triangles = 0;
  double seconds = 0.0;
};

// Keeps one bottom-level BVH per mesh, shared by its instances, across renders; each render casts at a
// top-level scene over the instances it is given, rebuilt when they change (a scene of millions of
// instances is never instanced whole). Conventions as EmbreeScene's: every top level is translated by
// the centre of the whole scene's world bounds for single precision (the frame of an EmbreeScene over
// every node, so nodes drawn here come out as its image to the bit), and every result is in world space.
class EmbreeNodeCaster {
 public:
  // Builds nothing yet. `scene` and `hierarchy` must outlive this object and stay unchanged.
  EmbreeNodeCaster(const Scene& scene, const Hierarchy& hierarchy);
  // Starts from every mesh BVH `prebuilt` (an EmbreeScene of the same scene) holds: shared, not copied,
  // and never built again here. `prebuilt` may be destroyed before this object.
  EmbreeNodeCaster(const Scene& scene, const Hierarchy& hierarchy, const EmbreeScene& prebuilt);
  ~EmbreeNodeCaster();
  EmbreeNodeCaster(EmbreeNodeCaster&&) noexcept;  // a moved-from caster may only be destroyed or assigned to
  EmbreeNodeCaster& operator=(EmbreeNodeCaster&&) noexcept;

  // EmbreeScene::render restricted to the mesh instances of `nodes`: overwrites every pixel of the
  // framebuffer's channels, a miss giving the cleared values. Instances outside the camera's clip
  // volume are left out (no ray inside it can reach them), so their meshes are not built for them.
  // Builds the missing mesh BVHs first and reports them. Deterministic for any thread count. Throws
  // std::invalid_argument when the framebuffer is not the camera's size.
  EmbreeBuilds render(const Camera& camera, std::span<const std::uint32_t> nodes, Framebuffer& framebuffer);

  // Notes the meshes render(camera, nodes, …) would draw as drawn, without building or casting anything:
  // what a frame passed over leaves for the frames after it (drawnBefore).
  void noteDrawn(const Camera& camera, std::span<const std::uint32_t> nodes);

  // Whether mesh `mesh`'s BVH is there now (built here, shared from a prebuilt scene, or not yet or no
  // longer: forget).
  bool built(std::uint32_t mesh) const;
  // Whether a render (or noteDrawn) of this caster has drawn mesh `mesh`: its history alone, whatever was
  // built, shared or forgotten since. A caller that weighs what a render would build asks this, so that
  // its choice depends on the frames drawn before, not on what another renderer built or a memory budget
  // let go (docs/evaluation.md, "The rasterizer's price of triangles on pixels").
  bool drawnBefore(std::uint32_t mesh) const;
  // Lets go of mesh `mesh`'s BVH, and of the top level that may hold it, before the mesh's arrays are
  // unloaded (LazyMeshes): the BVH reads the mesh's indices where they lie. A later render that needs the
  // mesh builds it again.
  void forget(std::uint32_t mesh);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;  // holds the Embree objects, so no Embree header leaks out of here
};

}  // namespace pbs
