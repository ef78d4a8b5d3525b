// The measuring half of `pbs eval`: a converged reference (Embree at many samples per pixel) of every
// view, each view's kind (near, mid, far), then every setting over the same views, each frame timed
// and compared with the reference of its view.
#pragma once

#include "pbs/evaluation/eval_settings.hpp"

#include <pbs/raster/camera.hpp>
#include <pbs/raster/image_metrics.hpp>
#include <pbs/scene/hierarchy.hpp>
#include <pbs/scene/scene.hpp>
#include <pbs/surfels/frame_kind.hpp>
#include <pbs/surfels/frame_renderer.hpp>
#include <pbs/surfels/lod_render.hpp>
#include <pbs/surfels/scene_surfels.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace pbs {

// One view of the path and what the reference found there.
struct EvalView {
  Camera camera;
  double referenceSeconds = 0.0;  // the reference frame's time
  double geometryShare = 0.0;     // of the reference's coverage, the share the baseline draws as geometry
  FrameKind kind = FrameKind::Far;
};

// One row of eval.csv.
struct EvalFrame {
  std::uint32_t frame = 0;
  // The whole frame (FrameResult::seconds) less reading surfels from the file; of EvalInputs::draws draws of
  // the view, the median one's (the lower middle one for an even count), as are `stats`.
  double seconds = 0.0;
  double surfelLoadSeconds = 0.0;  // reading the prefixes it drew that were not read yet (SurfelCache)
  // Building the BVHs of meshes its rays drew that had none yet, in its first draw: a part of `seconds` for
  // one draw, paid once a path, which the median of several draws leaves out.
  double bvhBuildSeconds = 0.0;
  double divisor = 1.0;  // a budget's lower resolution (FrameResult::divisor)
  LodStats stats;
  ImageDifference error;  // this frame (A) against the reference of the same view (B), without the map
  // The fastest peer's time on this frame (the least of the 1-sample peers': Embree and exact) over
  // this one's: how many times faster than the exact renderer a user has. 0 when no such peer ran.
  double speedupOverFastestExact = 0.0;
};

struct EvalSettingResult {
  std::vector<EvalFrame> frames;
  std::vector<std::uint8_t> sheetImage;  // the contact sheet's frame as RGBA8
  std::vector<std::uint8_t> sheetFlip;   // its FLIP map (flipMapRgba8)
};

struct EvalResults {
  std::vector<EvalView> views;
  std::vector<std::uint8_t> referenceSheet;  // the reference of the contact sheet's frame as RGBA8
  double buildSeconds = 0.0;                // Embree's BVH, built once for the reference and the Embree peers (0: none)
  std::vector<EvalSettingResult> settings;  // parallel to the settings given
};

struct EvalInputs {
  // The reference: Embree rays, or the rasterizer (with `meshes`, node by node: it needs no hierarchy over
  // every triangle), at this many samples per pixel.
  RenderMode referenceMode = RenderMode::Embree;
  std::uint32_t referenceSamples = 64;
  // How every setting's frames (peers included) sample textures; the reference keeps the cameras' own, the best.
  TextureFiltering textures = TextureFiltering::Anisotropic;
  // A scene opened without its mesh arrays: exact frames and surfel frames from the file's cache read the
  // meshes they draw through it (no setting may then use Embree over the whole scene).
  LazyMeshes* meshes = nullptr;
  CompareOptions compare;        // background and observer; the FLIP map is taken for the sheet's frame only
  std::uint32_t sheetFrame = 0;  // the frame the contact sheet shows
  // Draws of each view by each setting, one after the other: the first gives the image and its error, the
  // median time of all the frame's time. Later draws find what the first read and built (prefixes, mesh
  // BVHs) in place, as the frames after it on a path would; a renderer's first draw of a process also pays
  // for faulting in its buffers.
  int draws = 1;
  // The surfels and LOD options that decide each view's kind (the file's own arrays, the baseline), read
  // with one threshold for every node (descendExhausted off, whatever kindLod says).
  const SceneSurfels* kindSurfels = nullptr;
  LodOptions kindLod;
};

// Whether the reference (`reference`) or a setting casts Embree rays over the whole scene: its BVH holds
// every triangle, so the scene must be read whole.
bool castsRaysOverWholeScene(const std::vector<EvalSetting>& settings, RenderMode reference);

// Whether every setting and the reference can draw a scene whose meshes are read as frames draw them:
// not with Embree over the whole scene (its BVH holds every triangle), arrays of other orderings than
// the file's or simplified meshes (both made from the whole scene).
bool drawableWithMeshesOnDemand(const std::vector<EvalSetting>& settings, RenderMode reference,
                                SurfelOrdering fileOrdering);

// Renders the reference and views × settings frames. `surfelsOf` gives the arrays a surfel setting
// draws, as FrameSources::surfels (made in memory) or FrameSources::cache (the file, read as frames draw
// it: every setting of the file's own arrays shares one cache) (called once per setting, never for peers;
// simplify settings take their traversal's decisions from them), `simplifiedOf` the simplified scene a
// simplify setting draws (called once per such setting); `onProgress(done, total, detail)` after every
// frame. Memory: the reference images of all views are kept (16 bytes a pixel each).
EvalResults runEval(const Scene& scene, const Hierarchy& hierarchy, const std::vector<Camera>& cameras,
                    const std::vector<EvalSetting>& settings, const EvalInputs& inputs,
                    const std::function<FrameSources(const EvalSetting&)>& surfelsOf,
                    const std::function<const Scene&(const EvalSetting&)>& simplifiedOf,
                    const std::function<void(std::size_t, std::size_t, const std::string&)>& onProgress);

}  // namespace pbs
