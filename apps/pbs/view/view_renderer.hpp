// The frames `pbs view` sends: one request at a time rendered on all cores (a frame is already parallel
// inside), by renderers kept across requests so that buffers, mesh BVHs and loaded prefixes are reused.
#pragma once

#include "../frame_scene.hpp"
#include "view_request.hpp"

#include <pbs/raster/camera.hpp>
#include <pbs/scene/embree_caster.hpp>
#include <pbs/surfels/frame_renderer.hpp>

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

namespace pbs::cli {

struct ViewFrame {
  std::vector<std::uint8_t> rgba8;           // width × height, straight RGBA (colour 0 where alpha is 0)
  RenderMode drawnBy = RenderMode::Surfels;  // the shown frame's mode (the test frame for difference and FLIP)
  std::uint32_t samples = 1;
  double seconds = 0.0;  // every frame rendered for it (the reference too, unless it was kept)
  LodStats stats;        // the shown frame's
  // Difference and FLIP: the test frame's FLIP against the reference over the pixels either covers.
  std::optional<double> foregroundFlip;
};

class ViewRenderer {
 public:
  // `scene` must outlive the renderer; `maxMemory` (0: the machine's) bounds the rays' BVH.
  ViewRenderer(FrameScene& scene, std::uint64_t maxMemory);

  glm::dvec3 center() const { return center_; }
  double radius() const { return radius_; }
  bool hasSurfels() const { return scene_.surfels.has_value(); }
  // The request's camera: `pbs render --orbit`'s when the target is the centre.
  Camera camera(const ViewRequest& request) const;

  // Renders one request, after the requests before it. When its turn comes, `superseded` is asked
  // whether the client has asked for a newer frame meanwhile: then nothing is rendered (nullopt). Throws
  // std::invalid_argument for surfels without a file, std::runtime_error for rays whose BVH would not fit.
  std::optional<ViewFrame> render(const ViewRequest& request, const std::function<bool()>& superseded);

 private:
  // The whole scene's BVH, built on first use. Meshes read on demand are all read for it, and kept.
  const EmbreeScene& rays();
  FrameResult renderFrame(RenderMode mode, std::uint32_t samples, FrameImage image, const ViewRequest& request);
  // Difference or FLIP map of the surfel (else exact) frame against a 16-sample exact reference.
  ViewFrame renderComparison(const ViewRequest& request);

  struct Kept {
    RenderMode mode;
    SplatMode splat;
    std::uint32_t samples;
    FrameImage image;
    std::uint32_t width, height;
    std::unique_ptr<FrameRenderer> renderer;
    std::uint64_t lastUse;
  };
  struct Reference {
    glm::dmat4 clipFromWorld{0.0};
    std::uint32_t width = 0, height = 0;
    std::vector<glm::vec4> image;
  };

  FrameScene& scene_;
  glm::dvec3 center_{0.0};
  double radius_ = 1.0;
  std::mutex mutex_;  // one frame at a time: renderers, caches and BVHs are not shared between threads
  std::uint64_t maxMemory_;
  LazyMeshes::Lease everyMesh_;      // with meshes read on demand: what the rays hold
  std::optional<EmbreeScene> rays_;  // built for the first frame that casts rays at the whole scene
  std::vector<Kept> kept_;
  std::uint64_t uses_ = 0;
  Reference reference_;  // the last comparison's, reused while the camera rests
};

}  // namespace pbs::cli
