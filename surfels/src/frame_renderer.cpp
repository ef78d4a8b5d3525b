// FrameRenderer: one G-buffer reused across frames and samples, the mode's draw, the shared shading,
// and the supersampled passes summed and resolved.
#include "pbs/surfels/frame_renderer.hpp"

#include "elapsed.hpp"
#include "lod_budget.hpp"

#include <pbs/raster/headlight_shading.hpp>
#include <pbs/raster/image_upscale.hpp>
#include <pbs/raster/supersampling.hpp>
#include <pbs/raster/value_names.hpp>
#include <pbs/surfels/lod_geometry.hpp>
#include <pbs/surfels/simplified_lod.hpp>

#include <stdexcept>
#include <string>
#include <utility>

namespace pbs {
namespace {

constexpr ValueNames<RenderMode, 4> kModeNames{{{{RenderMode::Surfels, "surfels"},
                                                 {RenderMode::Exact, "exact"},
                                                 {RenderMode::Embree, "embree"},
                                                 {RenderMode::Simplified, "simplified"}}}};

constexpr ValueNames<TextureFiltering, 3> kFilteringNames{{{{TextureFiltering::Anisotropic, "anisotropic"},
                                                            {TextureFiltering::Isotropic, "isotropic"},
                                                            {TextureFiltering::None, "none"}}}};

// The camera a frame is drawn from: `camera`, its texture probes as `filtering` says.
Camera filteredCamera(const Camera& camera, TextureFiltering filtering) {
  Camera filtered = camera;
  if (filtering == TextureFiltering::Isotropic) filtered.textureProbes = 1;
  if (filtering == TextureFiltering::None) filtered.textureProbes = 0;
  return filtered;
}

// Only blended surfels leave pixels partly covered.
ChannelMask coverageChannel(const FrameOptions& options) {
  return options.mode == RenderMode::Surfels && options.lod.splat == SplatMode::Blend ? ChannelMask{kChannelCoverage}
                                                                                      : ChannelMask{0};
}

}  // namespace

std::optional<RenderMode> renderModeFromName(std::string_view name) { return kModeNames.parse(name); }

const char* renderModeName(RenderMode mode) { return kModeNames.name(mode).data(); }

const char* textureFilteringName(TextureFiltering filtering) { return kFilteringNames.name(filtering).data(); }

FrameRenderer::FrameRenderer(const Scene& scene, const Hierarchy& hierarchy, const FrameOptions& options,
                             std::uint32_t width, std::uint32_t height, const FrameSources& sources)
    : scene_(scene),
      hierarchy_(hierarchy),
      options_(options),
      sources_(sources),
      gbuffer_(makeFramebuffer(width, height, kChannelColor | kChannelNormal | coverageChannel(options))) {
  const RenderMode mode = options.mode;
  // From a cache, the arrays' decisions (lengths, packing) are there at once; surfels mode loads prefixes.
  if (sources.cache && !sources.surfels) sources_.surfels = &sources.cache->surfels();
  if (sources.stream && (mode != RenderMode::Surfels || !sources.cache))
    throw std::invalid_argument("a stream draws in surfels mode from its surfel cache");
  if (sources.meshes && mode != RenderMode::Exact && (mode != RenderMode::Surfels || !sources.cache || sources.stream))
    throw std::invalid_argument(
        "meshes read on demand are drawn in exact mode, or in surfels mode from a surfel cache without a stream");
  if ((mode == RenderMode::Surfels || mode == RenderMode::Simplified) && !sources_.surfels)
    throw std::invalid_argument("surfels and simplified modes need a surfel file");
  if (mode == RenderMode::Simplified && !sources.simplified)
    throw std::invalid_argument("simplified mode needs the simplified scene");
  if (!isSupportedSampleCount(options.samples))
    throw std::invalid_argument(std::to_string(options.samples) + " samples per pixel; supported: 1, 4, 16, 64, 256");
  if (mode == RenderMode::Embree && !sources.rays) {
    const auto build = detail::Clock::now();
    ownRays_.emplace(scene, hierarchy);
    buildSeconds_ = detail::secondsSince(build);
    sources_.rays = &*ownRays_;
  }
  if (mode == RenderMode::Surfels && options.lod.geometry != GeometryDrawer::Raster) {
    if (sources.rays)
      geometryRays_.emplace(scene, hierarchy, *sources.rays);
    else
      geometryRays_.emplace(scene, hierarchy);
  }
}

void FrameRenderer::setLod(const LodOptions& lod) {
  if (lod.splat != options_.lod.splat || lod.geometry != options_.lod.geometry)
    throw std::invalid_argument("a frame renderer keeps the splat mode and geometry drawer it was made with");
  options_.lod = lod;
}

void FrameRenderer::loadGeometry(const LodDraws& draws) {
  // The new frame's lease first, then the old one let go: a mesh both frames draw is never unloaded.
  geometryLease_ = sources_.meshes->requireDrawnBy(draws.geometryNodes);
  for (std::uint32_t mesh : sources_.meshes->unloadOverBudget())
    if (geometryRays_) geometryRays_->forget(mesh);
}

LodStats FrameRenderer::drawExactInBatches(const Camera& camera, Framebuffer& gbuffer, const LodOptions& lod,
                                           double& loadSeconds) {
  LodStats pass;
  const auto traverse = detail::Clock::now();
  const LodDraws draws = traverseLod(scene_, hierarchy_, none_, camera, lod);
  pass.traverseSeconds = detail::secondsSince(traverse);
  std::vector<std::uint32_t> nodes, meshes;
  std::uint64_t bytes = 0;
  const auto drawBatch = [&] {
    const auto load = detail::Clock::now();
    LazyMeshes::Lease lease = sources_.meshes->require(meshes);
    loadSeconds += detail::secondsSince(load);
    const auto raster = detail::Clock::now();
    drawLodGeometry(scene_, hierarchy_, nodes, camera, gbuffer, GeometryDrawer::Raster, nullptr);
    pass.rasterSeconds += detail::secondsSince(raster);
    lease = {};
    sources_.meshes->unloadOverBudget();
    nodes.clear();
    meshes.clear();
    bytes = 0;
  };
  for (std::uint32_t node : draws.geometryNodes) {
    const auto mesh = std::uint32_t(scene_.nodes[node].mesh);
    const std::uint64_t more = foreseenMeshBytes(scene_.meshes[mesh]);
    if (!nodes.empty() && bytes + more > sources_.meshes->budgetBytes()) drawBatch();
    nodes.push_back(node);
    meshes.push_back(mesh);
    bytes += more;
  }
  if (!nodes.empty()) drawBatch();
  pass.triangles = draws.triangles;
  pass.nodesGeometry = draws.geometryNodes.size();
  return pass;
}

LodDraws FrameRenderer::cut(const Camera& camera) const {
  if (options_.mode != RenderMode::Surfels) throw std::logic_error("FrameRenderer::cut: surfels mode only");
  return cutFor(camera, options_.lod);
}

LodDraws FrameRenderer::cutFor(const Camera& camera, const LodOptions& lod) const {
  // A stream's frames are the threshold's cuts (no rays to price: SurfelStream plans for surfels).
  return traverseLodForDrawer(scene_, hierarchy_, *sources_.surfels, camera, lod,
                              sources_.stream || !geometryRays_ ? nullptr : &*geometryRays_);
}

LodStats FrameRenderer::drawPass(const Camera& camera, Framebuffer& gbuffer, const LodOptions& lod, double& loadSeconds,
                                 const std::optional<LodDraws>& planned) {
  LodStats pass;
  if (passingOver_) {
    passOverLodGeometry(scene_, hierarchy_, (planned ? *planned : cutFor(camera, lod)).geometryNodes, camera,
                        lod.geometry, &*geometryRays_, lod.frameCosts, lod.bvhBuildFrames);
    return pass;
  }
  if (clearsDepth()) clearFramebuffer(gbuffer, 0);
  switch (options_.mode) {
    case RenderMode::Surfels: {
      EmbreeNodeCaster* rays = geometryRays_ ? &*geometryRays_ : nullptr;
      if (!sources_.cache) {
        pass = planned ? drawLod(scene_, hierarchy_, *sources_.surfels, *planned, camera, gbuffer, lod, rays)
                       : renderLod(scene_, hierarchy_, *sources_.surfels, camera, gbuffer, lod, rays);
        break;
      }
      // One traversal (unless choosing the resolution made it): the stream cuts it to what has arrived, or the
      // cache loads what it draws; then it is drawn.
      const auto traverse = detail::Clock::now();
      LodDraws draws = planned ? *planned : cutFor(camera, lod);
      const double traverseSeconds = detail::secondsSince(traverse);
      if (sources_.stream) {
        draws = sources_.stream->arrived(draws, camera);
      } else {
        const auto load = detail::Clock::now();
        sources_.cache->load(draws);
        if (sources_.meshes) loadGeometry(draws);
        loadSeconds += detail::secondsSince(load);
      }
      pass = drawLod(scene_, hierarchy_, *sources_.surfels, draws, camera, gbuffer, lod, rays);
      pass.traverseSeconds = traverseSeconds;
      break;
    }
    case RenderMode::Exact:
      pass = sources_.meshes ? drawExactInBatches(camera, gbuffer, lod, loadSeconds)
                             : renderLod(scene_, hierarchy_, none_, camera, gbuffer, lod);
      break;
    case RenderMode::Simplified:
      pass = renderSimplifiedLod(scene_, *sources_.simplified, hierarchy_, *sources_.surfels, camera, gbuffer, lod);
      break;
    case RenderMode::Embree: {
      const auto cast = detail::Clock::now();
      sources_.rays->render(camera, gbuffer);
      pass.rasterSeconds = detail::secondsSince(cast);
      break;
    }
  }
  return pass;
}

void FrameRenderer::fitGbuffer(const Camera& camera) {
  if (gbuffer_.width != camera.width || gbuffer_.height != camera.height)
    resizeFramebuffer(gbuffer_, camera.width, camera.height);
}

void FrameRenderer::renderReduced(const Camera& camera, const BudgetResolution& resolution, FrameResult& result) {
  const double divisor = resolution.divisor;
  const Camera reduced = reducedCamera(camera, divisor);
  // Drawn in the frame's own G-buffer, shrunk: its memory is already there, where a framebuffer of its own would
  // fault in tens of MB of fresh pages each time the divisor grows (10 ms and more on 2 cores).
  fitGbuffer(reduced);
  LodOptions lod = options_.lod;
  lod.budget = resolution.pass;
  result.stats = drawPass(reduced, gbuffer_, lod, result.surfelLoadSeconds, resolution.draws);
  result.divisor = divisor;
  result.drawnWidth = reduced.width;
  result.drawnHeight = reduced.height;
  if (options_.image == FrameImage::None) return;
  // Shaded a row at a time as the upscale reads it: no image of the lower resolution is held.
  const HeadlightShader shader(gbuffer_, reduced);
  const UpscaleRows rows = [&](std::uint32_t y, glm::vec4* scratch) {
    shader.shadeRow(y, scratch);
    return scratch;
  };
  if (options_.image == FrameImage::Rgba8)
    result.rgba8 = upscaleBilinearRgba8(rows, reduced.width, reduced.height, camera.width, camera.height);
  else
    result.image = upscaleBilinear(rows, reduced.width, reduced.height, camera.width, camera.height);
}

void FrameRenderer::passOver(const Camera& camera) {
  if (options_.mode != RenderMode::Surfels || !geometryRays_ || sources_.stream) return;
  // render() itself, so that its passes are the ones a drawn frame makes; drawPass only chooses and notes, and
  // nothing is shaded. Restored however render() ends.
  struct Restore {
    FrameRenderer& renderer;
    FrameImage image;
    ~Restore() {
      renderer.passingOver_ = false;
      renderer.options_.image = image;
    }
  };
  const Restore restore{*this, std::exchange(options_.image, FrameImage::None)};
  passingOver_ = true;
  render(camera);
}

FrameResult FrameRenderer::render(const Camera& camera) {
  const Camera view = filteredCamera(camera, options_.textures);
  FrameResult result;
  result.drawnWidth = view.width;
  result.drawnHeight = view.height;
  const auto start = detail::Clock::now();
  const BudgetResolution resolution = options_.mode == RenderMode::Surfels && options_.samples == 1
                                          ? budgetResolution(scene_, hierarchy_, *sources_.surfels, view, options_.lod)
                                          : BudgetResolution{.divisor = 1.0, .pass = options_.lod.budget};
  if (resolution.divisor > 1.0) {
    renderReduced(view, resolution, result);
  } else if (options_.samples == 1) {
    fitGbuffer(view);
    result.stats = drawPass(view, gbuffer_, options_.lod, result.surfelLoadSeconds, resolution.draws);
    if (options_.image == FrameImage::Float) result.image = shadeHeadlight(gbuffer_, view);
    if (options_.image == FrameImage::Rgba8) result.rgba8 = shadeHeadlightRgba8(gbuffer_, view);
  } else {
    fitGbuffer(view);
    SampleSums sums;
    if (options_.image != FrameImage::None) sums.sums.assign(gbuffer_.pixelCount(), glm::vec4(0.0f));
    bool firstPass = true;
    for (const glm::dvec2& sample : subpixelSamples(options_.samples)) {
      const Camera shifted = subpixelCamera(view, sample, options_.samples);
      const LodStats pass = drawPass(shifted, gbuffer_, options_.lod, result.surfelLoadSeconds);
      // Counts are the first pass's (every pass draws about the same); times add up.
      if (firstPass) {
        result.stats = pass;
        firstPass = false;
      } else {
        result.stats.traverseSeconds += pass.traverseSeconds;
        result.stats.rasterSeconds += pass.rasterSeconds;
        result.stats.geometrySeconds += pass.geometrySeconds;
        result.stats.bvhBuildSeconds += pass.bvhBuildSeconds;
      }
      if (options_.image != FrameImage::None) accumulateHeadlight(gbuffer_, shifted, sums);
    }
    if (options_.image != FrameImage::None) result.image = resolveSamples(sums);
    if (options_.image == FrameImage::Rgba8) result.rgba8 = toRgba8(std::exchange(result.image, {}));
  }
  // Choosing a budget's resolution traversed the cut the frame drew (and any it weighed against it).
  result.stats.traverseSeconds += resolution.traverseSeconds;
  result.seconds = detail::secondsSince(start);
  return result;
}

}  // namespace pbs
