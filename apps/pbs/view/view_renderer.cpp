// ViewRenderer: a small set of frame renderers kept by what they were made for, the whole scene's BVH
// built on first use, and the comparisons against a 16-sample reference kept while the camera rests.
#include "view_renderer.hpp"

#include "../memory_limit.hpp"

#include <pbs/raster/flip.hpp>
#include <pbs/raster/headlight_shading.hpp>
#include <pbs/raster/image_metrics.hpp>
#include <pbs/surfels/camera_paths.hpp>

#include <algorithm>
#include <chrono>
#include <numeric>
#include <stdexcept>

namespace pbs::cli {
namespace {

// Renderers kept at once: a few sizes and modes a user toggles between. Each holds a G-buffer (36 bytes
// a pixel at most) and, in surfels mode, the BVHs of the meshes it cast rays at.
constexpr std::size_t kKeptRenderers = 6;
constexpr std::uint32_t kReferenceSamples = 16;
constexpr float kDifferenceGain = 4.0f;  // |test − reference| × this, so small errors show

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

ViewRenderer::ViewRenderer(FrameScene& scene, std::uint64_t maxMemory) : scene_(scene), maxMemory_(maxMemory) {
  // The orbit paths' centre and radius, so that a camera at the centre is `pbs render --orbit`'s.
  const Bounds bounds = sceneBounds(scene.loaded.hierarchy, scene.loaded.scene.roots);
  if (!bounds.empty()) center_ = bounds.center();
  radius_ = 0.5 * glm::length(bounds.size());
}

Camera ViewRenderer::camera(const ViewRequest& request) const {
  return orbitCamera(request.target, center_, radius_, request.orbit, request.width, request.height);
}

const EmbreeScene& ViewRenderer::rays() {
  if (rays_) return *rays_;
  const Scene& scene = scene_.loaded.scene;
  std::uint64_t meshBytes = 0;
  for (const Mesh& mesh : scene.meshes) meshBytes += foreseenMeshBytes(mesh);
  requireMemory(scene_.foreseenBytes + meshBytes + embreeMemoryEstimate(scene, scene_.loaded.hierarchy),
                "ray casting " + scene_.loaded.name, maxMemory_);
  if (scene_.meshes) {
    std::vector<std::uint32_t> all(scene.meshes.size());
    std::iota(all.begin(), all.end(), 0u);
    everyMesh_ = scene_.meshes->require(all);
  }
  return rays_.emplace(scene, scene_.loaded.hierarchy);
}

FrameResult ViewRenderer::renderFrame(RenderMode mode, std::uint32_t samples, FrameImage image,
                                      const ViewRequest& request) {
  if (mode == RenderMode::Surfels && !hasSurfels())
    throw std::invalid_argument("show=surfels: no .surfels file (start pbs view with --surfels FILE)");
  const SplatMode splat = request.lod.splat;
  auto kept = std::find_if(kept_.begin(), kept_.end(), [&](const Kept& k) {
    return k.mode == mode && (mode != RenderMode::Surfels || k.splat == splat) && k.samples == samples &&
           k.image == image && k.width == request.width && k.height == request.height;
  });
  if (kept == kept_.end()) {
    if (kept_.size() == kKeptRenderers)
      kept_.erase(std::min_element(kept_.begin(), kept_.end(),
                                   [](const Kept& a, const Kept& b) { return a.lastUse < b.lastUse; }));
    FrameSources sources{.cache = mode == RenderMode::Surfels ? &*scene_.surfels : nullptr,
                         .meshes = scene_.meshes && mode != RenderMode::Embree ? &*scene_.meshes : nullptr,
                         .rays = mode == RenderMode::Embree ? &rays() : nullptr};
    auto renderer = std::make_unique<FrameRenderer>(
        scene_.loaded.scene, scene_.loaded.hierarchy,
        FrameOptions{.mode = mode, .lod = request.lod, .samples = samples, .image = image}, request.width,
        request.height, sources);
    kept_.push_back({mode, splat, samples, image, request.width, request.height, std::move(renderer), 0});
    kept = std::prev(kept_.end());
  }
  kept->lastUse = ++uses_;
  if (mode == RenderMode::Surfels) kept->renderer->setLod(request.lod);
  return kept->renderer->render(camera(request));
}

ViewFrame ViewRenderer::renderComparison(const ViewRequest& request) {
  const auto start = std::chrono::steady_clock::now();
  const RenderMode testMode = hasSurfels() ? RenderMode::Surfels : RenderMode::Embree;
  const FrameResult test = renderFrame(testMode, request.samples, FrameImage::Float, request);
  const Camera view = camera(request);
  if (reference_.clipFromWorld != view.clipFromWorld() || reference_.width != request.width ||
      reference_.height != request.height) {
    reference_ = {view.clipFromWorld(), request.width, request.height,
                  renderFrame(RenderMode::Embree, kReferenceSamples, FrameImage::Float, request).image};
  }
  const RgbaImage a{request.width, request.height, test.image};
  const RgbaImage b{request.width, request.height, reference_.image};
  const ImageDifference difference = compareImages(a, b, {.keepFlipMap = request.show == ViewShow::Flip});
  ViewFrame frame;
  frame.drawnBy = testMode;
  frame.samples = request.samples;
  frame.stats = test.stats;
  frame.foregroundFlip = difference.flipForegroundMean;
  if (request.show == ViewShow::Flip) {
    frame.rgba8 = flipMapRgba8(difference.flipMap);
  } else {
    // Both over white, as the comparison sees them.
    std::vector<glm::vec4> shown(test.image.size());
    for (std::size_t i = 0; i < shown.size(); ++i) {
      const glm::vec4 p = test.image[i], q = reference_.image[i];
      const glm::vec3 over = glm::vec3(p) * p.a + (1.0f - p.a) - (glm::vec3(q) * q.a + (1.0f - q.a));
      shown[i] = glm::vec4(glm::min(glm::abs(over) * kDifferenceGain, glm::vec3(1.0f)), 1.0f);
    }
    frame.rgba8 = toRgba8(shown);
  }
  frame.seconds = secondsSince(start);
  return frame;
}

std::optional<ViewFrame> ViewRenderer::render(const ViewRequest& request, const std::function<bool()>& superseded) {
  const std::lock_guard lock(mutex_);
  if (superseded()) return std::nullopt;
  if (request.show == ViewShow::Difference || request.show == ViewShow::Flip) return renderComparison(request);
  const RenderMode mode = request.show == ViewShow::Surfels ? RenderMode::Surfels
                          : request.show == ViewShow::Exact ? RenderMode::Exact
                                                            : RenderMode::Embree;
  const auto start = std::chrono::steady_clock::now();
  FrameResult result = renderFrame(mode, request.samples, FrameImage::Rgba8, request);
  ViewFrame frame;
  frame.rgba8 = std::move(result.rgba8);
  frame.drawnBy = mode;
  frame.samples = request.samples;
  frame.seconds = secondsSince(start);
  frame.stats = result.stats;
  return frame;
}

}  // namespace pbs::cli
