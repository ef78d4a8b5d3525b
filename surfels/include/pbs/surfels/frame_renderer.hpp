// One frame of a scene in any render mode, timed and optionally supersampled: what `pbs render`,
// `pbs eval` and the figures repeat per view.
#pragma once

#include "pbs/raster/camera.hpp"
#include "pbs/raster/framebuffer.hpp"
#include "pbs/scene/embree_caster.hpp"
#include "pbs/scene/embree_node_caster.hpp"
#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/lazy_meshes.hpp"
#include "pbs/surfels/lod_render.hpp"
#include "pbs/surfels/surfel_cache.hpp"
#include "pbs/surfels/surfel_stream.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace pbs {

struct BudgetResolution;  // lod_budget.hpp: how a budget in seconds draws a frame

// Exact: the rasterizer draws every visible mesh. Embree: rays, one per sample. Surfels: the LOD
// traversal with surfel prefixes for small nodes. Simplified: the same traversal, small nodes drawn
// from a simplified copy of the scene (simplified_lod.hpp).
enum class RenderMode { Surfels, Exact, Embree, Simplified };

// "surfels", "exact", "embree", "simplified"; nullopt for any other name.
std::optional<RenderMode> renderModeFromName(std::string_view name);
const char* renderModeName(RenderMode mode);

// What a frame's image is made as: the shaded float image (for comparisons and float files), its 8-bit
// conversion alone (for 8-bit files: no float image is held), or none (frames only timed and counted).
enum class FrameImage { Float, Rgba8, None };

// How a frame's textures are filtered: as its cameras say (Anisotropic: Camera::textureProbes, up to 4 probes
// along a footprint longer than wide), with one probe (Isotropic, OpenGL's rule), or from level 0 alone
// (None: no mip level, no probe: the fastest, and aliased where textures are minified).
enum class TextureFiltering { Anisotropic, Isotropic, None };

// "anisotropic", "isotropic", "none".
const char* textureFilteringName(TextureFiltering filtering);

struct FrameOptions {
  RenderMode mode = RenderMode::Exact;
  LodOptions lod{};  // surfels and simplified modes
  // Samples per pixel (supersampling.hpp: 1, 4, 16, 64, 256): each a whole pass at its sub-pixel
  // position, shaded and summed, then box-filtered into colour with fractional alpha. Memory does not
  // grow with the count: one G-buffer and one sum image.
  std::uint32_t samples = 1;
  FrameImage image = FrameImage::Float;
  TextureFiltering textures = TextureFiltering::Anisotropic;
};

struct FrameResult {
  // Shaded (headlight_shading.hpp), straight RGBA: alpha is the fraction of samples that hit a surface
  // (0 or 1 at one sample), colour (0, 0, 0) where it is 0.
  std::vector<glm::vec4> image;
  std::vector<std::uint8_t> rgba8;  // FrameImage::Rgba8 instead of `image`: toRgba8(image), 4 bytes a pixel
  double seconds = 0.0;             // every pass: clear, traverse, raster or rays, shading; plus the resolve
  // Of those, reading prefixes on demand (FrameSources::cache) and meshes on demand (FrameSources::meshes).
  double surfelLoadSeconds = 0.0;
  // Traversal and raster times summed over the passes; the counts are those of one pass.
  LodStats stats;
  // A budget in seconds that lowered the resolution (LodBudget::lowerResolution): the passes were drawn at
  // drawnWidth × drawnHeight, the frame's size divided by `divisor`, and the shaded image upscaled.
  double divisor = 1.0;
  std::uint32_t drawnWidth = 0, drawnHeight = 0;

  // `seconds` less what is paid once rather than every frame (reading prefixes, building a mesh's BVH):
  // what a frame's cost model predicts (frame_cost.hpp).
  double recurringSeconds() const { return seconds - surfelLoadSeconds - stats.bvhBuildSeconds; }
};

// What a mode draws from besides the scene; each must outlive the renderer.
struct FrameSources {
  const SceneSurfels* surfels = nullptr;  // Surfels and Simplified modes (Simplified takes its decisions from them)
  // Instead of `surfels`: a file read as frames draw it; in surfels mode each pass first loads the
  // prefixes it will draw (Simplified mode takes only the arrays' decisions from it).
  SurfelCache* cache = nullptr;
  // Surfels mode with `cache`: a link that the caller advances between frames (the stream's cache must
  // be `cache`); each pass draws only what has arrived, and loads nothing itself.
  const SurfelStream* stream = nullptr;
  // For a scene opened without its mesh arrays (lazy_meshes.hpp). Surfels mode, with `cache` and no
  // stream: each pass first loads the meshes of the nodes it draws as geometry, and unloads others past the
  // budget. Exact mode: each pass draws the visible meshes a budget's worth at a time, each batch loaded
  // for its drawing alone, so a scene larger than memory is drawn node by node (the same image).
  LazyMeshes* meshes = nullptr;
  const Scene* simplified = nullptr;  // Simplified mode: the scene's simplifyScene copy
  // Embree mode: a BVH built elsewhere and shared; null: built here. Surfels mode: mesh BVHs the geometry
  // nodes' rays reuse; null: each built the first time a frame needs it. Either way the drawer's price of a
  // build follows this renderer's own frames (EmbreeNodeCaster::drawnBefore), so they draw the same.
  const EmbreeScene* rays = nullptr;
};

class FrameRenderer {
 public:
  // Scene and hierarchy must outlive the renderer. In Embree mode without sources.rays the BVH is built
  // here (buildSeconds()). Throws std::invalid_argument for a missing source or an unsupported sample
  // count.
  FrameRenderer(const Scene& scene, const Hierarchy& hierarchy, const FrameOptions& options, std::uint32_t width,
                std::uint32_t height, const FrameSources& sources = {});

  // Bit-identical for any thread count. The camera must be width × height. A budget in seconds may draw it
  // at a lower resolution (FrameResult::divisor); only with one sample per pixel.
  FrameResult render(const Camera& camera);
  // What render(camera) leaves for the frames after it, without drawing, loading or shading anything: the
  // passes' cuts and geometry drawers are chosen as render would, and the meshes it would draw by rays are
  // noted as drawn (EmbreeNodeCaster::noteDrawn), since the drawer's choice prices BVHs still to build. A
  // renderer that passes over frames 0…k-1 of a path draws frame k as one that rendered them: a shard's
  // frames are the unsharded run's. Nothing in modes other than surfels, or without a ray caster.
  void passOver(const Camera& camera);
  // Surfels mode: the cut a full-resolution frame from `camera` draws with the current LOD options
  // (traverseLodForDrawer, with this renderer's ray caster), for a caller that shows or picks what drew it.
  // std::logic_error in another mode.
  LodDraws cut(const Camera& camera) const;
  // What every frame uses, for reports: the G-buffer's channels (coverage only for blended surfels), and
  // whether each pass clears its depth (the rasterizer's modes: colour and normal are read only where
  // depth says a pixel is covered, so they are never cleared) or clears nothing (Embree writes every
  // pixel). A frame draws `samples` passes, each shaded into the frame's image.
  ChannelMask channels() const { return gbuffer_.channels; }
  bool clearsDepth() const { return options_.mode != RenderMode::Embree; }
  double buildSeconds() const { return buildSeconds_; }  // 0 unless this renderer built the BVH
  // The budget the next frames spend (BudgetFeedback corrects it between frames).
  void setBudget(const LodBudget& budget) { options_.lod.budget = budget; }
  // The LOD options of the next frames (a viewer's sliders). Their splat mode and geometry drawer must be
  // the ones the renderer was made with, which decide its channels and its ray caster
  // (std::invalid_argument).
  void setLod(const LodOptions& lod);
  // Embree's peak allocation while building it (EmbreeScene::peakBytes); 0 unless this renderer built it.
  std::uint64_t bvhPeakBytes() const { return ownRays_ ? ownRays_->peakBytes() : 0; }

 private:
  // One pass at the camera's pixel centres into `gbuffer` (the camera's size) under `lod` (the frame's, or
  // a lower resolution's with the upscale taken out of its budget); adds its prefix and mesh loading to
  // `loadSeconds`. `planned`: the cut traverseLod would make with these arguments, already made.
  LodStats drawPass(const Camera& camera, Framebuffer& gbuffer, const LodOptions& lod, double& loadSeconds,
                    const std::optional<LodDraws>& planned = std::nullopt);
  // One pass at a budget's lower resolution under the budget left for it, shaded and upscaled to the camera's
  // size.
  void renderReduced(const Camera& camera, const BudgetResolution& resolution, FrameResult& result);
  // The cut a surfels pass under `lod` draws (traverseLodForDrawer with this renderer's ray caster).
  LodDraws cutFor(const Camera& camera, const LodOptions& lod) const;
  // The G-buffer at the camera's size: the frame's, or smaller for a budget's lower resolution (its memory
  // kept, its pixels unspecified until a pass clears them).
  void fitGbuffer(const Camera& camera);
  // Makes the meshes of `draws`' geometry nodes loaded (sources_.meshes), letting the ray caster forget
  // those unloaded to stay within the budget.
  void loadGeometry(const LodDraws& draws);
  // Exact mode's pass with sources_.meshes: the visible meshes drawn by the rasterizer in batches of at
  // most the budget (one mesh at least), in traversal order, each batch leased while drawn.
  LodStats drawExactInBatches(const Camera& camera, Framebuffer& gbuffer, const LodOptions& lod, double& loadSeconds);

  const Scene& scene_;
  const Hierarchy& hierarchy_;
  FrameOptions options_;
  FrameSources sources_;
  SceneSurfels none_;    // exact mode: the LOD traversal with no arrays draws every visible mesh
  Framebuffer gbuffer_;  // made at the frame's size; a budget's lower resolutions shrink it (fitGbuffer)
  std::optional<EmbreeScene> ownRays_;
  std::optional<EmbreeNodeCaster> geometryRays_;  // Surfels mode, unless LodOptions::geometry is Raster
  LazyMeshes::Lease geometryLease_;               // the meshes the last pass drew as geometry (FrameSources::meshes)
  double buildSeconds_ = 0.0;
  bool passingOver_ = false;  // passOver: passes choose and note, and draw nothing
};

}  // namespace pbs
