// FrameRenderer: one G-buffer reused across frames, the mode's draw, the shared shading.
#include "frame_renderer.hpp"

#include "report_numbers.hpp"

#include <pbs/raster/headlight_shading.hpp>
#include <pbs/surfels/simplified_lod.hpp>

#include <chrono>
#include <stdexcept>

namespace pbs::cli {

using Clock = std::chrono::steady_clock;

FrameRenderer::FrameRenderer(const Scene& scene, const Hierarchy& hierarchy, RenderMode mode,
                             const SceneSurfels* surfels, const LodOptions& lod, std::uint32_t width,
                             std::uint32_t height, const Scene* simplified)
    : scene_(scene),
      hierarchy_(hierarchy),
      mode_(mode),
      surfels_(surfels),
      simplified_(simplified),
      lod_(lod),
      gbuffer_(makeFramebuffer(width, height, kChannelColor | kChannelNormal)) {
  if ((mode == RenderMode::Surfels || mode == RenderMode::Simplified) && !surfels)
    throw std::invalid_argument("surfels and simplified modes need a surfel file");
  if (mode == RenderMode::Simplified && !simplified)
    throw std::invalid_argument("simplified mode needs the simplified scene");
  if (mode == RenderMode::Embree) {
    const auto start = Clock::now();
    embree_.emplace(scene, hierarchy);
    buildSeconds_ = secondsSince(start);
  }
}

FrameResult FrameRenderer::render(const Camera& camera) {
  FrameResult result;
  const auto start = Clock::now();
  // Embree overwrites every pixel itself; the rasterizer draws into a cleared G-buffer.
  if (mode_ != RenderMode::Embree) clearFramebuffer(gbuffer_);
  switch (mode_) {
    case RenderMode::Surfels: result.stats = renderLod(scene_, hierarchy_, *surfels_, camera, gbuffer_, lod_); break;
    case RenderMode::Exact: result.stats = renderLod(scene_, hierarchy_, none_, camera, gbuffer_, lod_); break;
    case RenderMode::Simplified:
      result.stats = renderSimplifiedLod(scene_, *simplified_, hierarchy_, *surfels_, camera, gbuffer_, lod_);
      break;
    case RenderMode::Embree: {
      const auto cast = Clock::now();
      embree_->render(camera, gbuffer_);
      result.stats.rasterSeconds = secondsSince(cast);
      break;
    }
  }
  result.image = shadeHeadlight(gbuffer_, camera);
  result.seconds = secondsSince(start);
  return result;
}

}  // namespace pbs::cli
