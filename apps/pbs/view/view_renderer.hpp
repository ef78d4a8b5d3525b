// The frames `pbs view` sends: one request at a time rendered on all cores (a frame is already parallel
// inside), by renderers kept across requests so that buffers, mesh BVHs and loaded prefixes are reused.
#pragma once

#include "../frame_scene.hpp"
#include "view_request.hpp"

#include <pbs/raster/camera.hpp>
#include <pbs/scene/embree_caster.hpp>
#include <pbs/surfels/frame_renderer.hpp>

#include <glm/glm.hpp>

#include <atomic>
#include <cstdint>
#include <filesystem>
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

// What a visible node drew in a frame, for the page's overlay of node boxes.
enum class DrawKind { Geometry, Surfels, Band };  // Band: a prefix a transition thins (count < full)
const char* drawKindName(DrawKind kind);
struct NodeDraw {
  std::uint32_t node = 0;
  DrawKind kind = DrawKind::Geometry;
  glm::dvec4 rect{0.0};  // x0, y0, x1, y1: the projected box's bounding rectangle, clipped to the frame
  double size = 0.0;     // projected size, pixels (the threshold's measure)
  std::uint32_t surfels = 0, full = 0;
  std::uint64_t triangles = 0;
};

class ViewRenderer {
 public:
  // `scene` must outlive the renderer; `maxMemory` (0: the machine's) bounds the rays' BVH. Frames filter
  // their textures by `textures`; the comparisons' reference by the default, as `pbs eval`'s does.
  ViewRenderer(FrameScene& scene, std::uint64_t maxMemory, TextureFiltering textures = TextureFiltering::Anisotropic);

  glm::dvec3 center() const { return center_; }
  double radius() const { return radius_; }
  bool hasSurfels() const { return hasSurfels_; }
  // Draws with `file` (made for this scene) from the next frame on: surfels made in the background.
  void attachSurfels(const std::filesystem::path& file);
  FrameScene& scene() { return scene_; }
  // The request's camera: `pbs render --orbit`'s when the target is the centre.
  Camera camera(const ViewRequest& request) const;

  // Renders one request, after the requests before it. When its turn comes, `superseded` is asked
  // whether the client has asked for a newer frame meanwhile: then nothing is rendered (nullopt). Throws
  // std::invalid_argument for surfels without a file, std::runtime_error for rays whose BVH would not fit.
  std::optional<ViewFrame> render(const ViewRequest& request, const std::function<bool()>& superseded);
  // The nodes the request's frame draws, largest on screen first, at most `limit`.
  std::vector<NodeDraw> nodeDraws(const ViewRequest& request, std::size_t limit);
  // The node that drew pixel (request.x, request.y) of the request's surfel frame, if any.
  std::optional<std::uint32_t> pick(const ViewRequest& request);
  // Runs `work` with the renderer's lock held (a node's inspection reads the caches frames use).
  template <typename Work>
  auto locked(Work&& work) {
    const std::lock_guard lock(mutex_);
    return work();
  }

 private:
  // The whole scene's BVH, built on first use. Meshes read on demand are all read for it, and kept.
  const EmbreeScene& rays();
  FrameResult renderFrame(RenderMode mode, std::uint32_t samples, FrameImage image, TextureFiltering textures,
                          const ViewRequest& request);
  // The renderer kept for these settings (made, dropping the least recently used, if none is), its LOD options
  // the request's.
  FrameRenderer& keptRenderer(RenderMode mode, std::uint32_t samples, FrameImage image, TextureFiltering textures,
                              const ViewRequest& request);
  // Difference or FLIP map of the surfel (else exact) frame against a 16-sample exact reference.
  ViewFrame renderComparison(const ViewRequest& request);
  // `draws` (with their prefixes loaded and their meshes leased here) into a G-buffer with node ids.
  Framebuffer drawWithIds(const LodDraws& draws, const ViewRequest& request);
  // The surfel frame tinted by what drew each pixel.
  ViewFrame renderSources(const ViewRequest& request);
  // Node request.node's first request.prefix surfels alone, at the size that prefix closes the surface.
  ViewFrame renderPrefix(const ViewRequest& request);
  LodDraws traverse(const ViewRequest& request);
  void requireSurfels() const;  // std::invalid_argument without surfels

  struct Kept {
    RenderMode mode;
    SplatMode splat;
    std::uint32_t samples;
    FrameImage image;
    TextureFiltering textures;
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
  TextureFiltering textures_;
  std::atomic<bool> hasSurfels_;     // scene_.surfels is set (read without the lock by the server)
  LazyMeshes::Lease everyMesh_;      // with meshes read on demand: what the rays hold
  std::optional<EmbreeScene> rays_;  // built for the first frame that casts rays at the whole scene
  std::vector<Kept> kept_;
  std::uint64_t uses_ = 0;
  Reference reference_;  // the last comparison's, reused while the camera rests
};

}  // namespace pbs::cli
