// One frame of a scene in any render mode, timed: what `pbs render` (and `pbs eval`) repeat per view.
#pragma once

#include <pbs/raster/camera.hpp>
#include <pbs/raster/framebuffer.hpp>
#include <pbs/scene/embree_caster.hpp>
#include <pbs/scene/hierarchy.hpp>
#include <pbs/surfels/lod_render.hpp>

#include <glm/glm.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace pbs::cli {

// Simplified: surfels' traversal, small nodes drawn from a simplified copy of the scene (simplified_lod.hpp).
enum class RenderMode { Surfels, Exact, Embree, Simplified };

struct FrameResult {
  std::vector<glm::vec4> image;  // shaded (headlight_shading.hpp), linear RGBA, alpha 0 = background
  double seconds = 0.0;          // clear + traverse + raster (or ray casting) + shading
  LodStats stats;                // traversal and raster split, counts (exact: geometry only; embree: none)
};

class FrameRenderer {
 public:
  // `surfels` is needed by (and only read in) RenderMode::Surfels and Simplified, `simplified` (the
  // scene's simplifyScene copy) by Simplified alone; all of them, scene and hierarchy must outlive the
  // renderer. Embree's BVH is built here (buildSeconds()).
  FrameRenderer(const Scene& scene, const Hierarchy& hierarchy, RenderMode mode, const SceneSurfels* surfels,
                const LodOptions& lod, std::uint32_t width, std::uint32_t height, const Scene* simplified = nullptr);

  FrameResult render(const Camera& camera);
  double buildSeconds() const { return buildSeconds_; }

 private:
  const Scene& scene_;
  const Hierarchy& hierarchy_;
  RenderMode mode_;
  const SceneSurfels* surfels_;
  const Scene* simplified_;
  SceneSurfels none_;  // exact mode: the LOD traversal with no arrays draws every visible mesh
  LodOptions lod_;
  Framebuffer gbuffer_;
  std::optional<EmbreeScene> embree_;
  double buildSeconds_ = 0.0;
};

}  // namespace pbs::cli
