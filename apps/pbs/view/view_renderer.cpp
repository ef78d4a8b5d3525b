// ViewRenderer: a small set of frame renderers kept by what they were made for, the whole scene's BVH
// built on first use, and the comparisons against a 16-sample reference kept while the camera rests.
#include "view_renderer.hpp"

#include "../memory_limit.hpp"

#include <pbs/evaluation/contact_sheet.hpp>
#include <pbs/evaluation/report_numbers.hpp>
#include <pbs/raster/flip.hpp>
#include <pbs/raster/headlight_shading.hpp>
#include <pbs/raster/image_metrics.hpp>
#include <pbs/raster/projected_box.hpp>
#include <pbs/surfels/camera_paths.hpp>

#include <algorithm>
#include <chrono>
#include <limits>
#include <numeric>
#include <unordered_map>
#include <stdexcept>

namespace pbs::cli {
namespace {

// Renderers kept at once: a few sizes and modes a user toggles between. Each holds a G-buffer (36 bytes
// a pixel at most) and, in surfels mode, the BVHs of the meshes it cast rays at.
constexpr std::size_t kKeptRenderers = 6;
constexpr std::uint32_t kFlipReferenceSamples = 16;
constexpr float kDifferenceGain = 4.0f;  // |test − reference| × this, so small errors show

// The overlay's colours: geometry blue, surfels orange, a band's thinned prefixes magenta.
constexpr glm::vec3 kKindColors[] = {{0.20f, 0.47f, 0.96f}, {0.96f, 0.55f, 0.12f}, {0.80f, 0.16f, 0.80f}};

// Each drawn node's kind; a node that draws both its mesh and a prefix is in a band.
std::unordered_map<std::uint32_t, DrawKind> kindsOf(const LodDraws& draws) {
  std::unordered_map<std::uint32_t, DrawKind> kinds;
  for (std::uint32_t node : draws.geometryNodes) kinds[node] = DrawKind::Geometry;
  for (const LodDraws::Surfels& draw : draws.surfels) {
    const auto [at, added] = kinds.try_emplace(draw.node, DrawKind::Surfels);
    if (!added || draw.count < draw.full) at->second = DrawKind::Band;
  }
  return kinds;
}

// The bounding rectangle of the box's corners in the window, clipped to it; the whole frame when a
// corner lies behind the eye.
glm::dvec4 projectedRect(const Camera& camera, const Bounds& box) {
  const glm::dmat4 clipFromWorld = camera.clipFromWorld();
  glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 p((corner & 1) ? box.max.x : box.min.x, (corner & 2) ? box.max.y : box.min.y,
                       (corner & 4) ? box.max.z : box.min.z);
    const glm::dvec4 clip = clipFromWorld * glm::dvec4(p, 1.0);
    if (!(clip.w > 0.0)) return {0.0, 0.0, double(camera.width), double(camera.height)};
    const glm::dvec2 window(windowFromClip(camera, clip));
    lo = glm::min(lo, window);
    hi = glm::max(hi, window);
  }
  const glm::dvec2 size(camera.width, camera.height);
  lo = glm::clamp(lo, glm::dvec2(0.0), size);
  hi = glm::clamp(hi, glm::dvec2(0.0), size);
  return {lo.x, lo.y, hi.x, hi.y};
}

}  // namespace

const char* drawKindName(DrawKind kind) {
  return kind == DrawKind::Geometry ? "geometry" : kind == DrawKind::Surfels ? "surfels" : "band";
}

ViewRenderer::ViewRenderer(FrameScene& scene, std::uint64_t maxMemory, TextureFiltering textures)
    : scene_(scene), maxMemory_(maxMemory), textures_(textures), hasSurfels_(scene.surfels.has_value()) {
  // The orbit paths' centre and radius, so that a camera at the centre is `pbs render --orbit`'s.
  const Bounds bounds = sceneBounds(scene.loaded.hierarchy, scene.loaded.scene.roots);
  if (!bounds.empty()) center_ = bounds.center();
  radius_ = 0.5 * glm::length(bounds.size());
}

Camera ViewRenderer::camera(const ViewRequest& request) const {
  return orbitCamera(request.target, center_, radius_, request.orbit, request.width, request.height);
}

void ViewRenderer::requireSurfels() const {
  if (!hasSurfels())
    throw std::invalid_argument("no .surfels file (start pbs view with --surfels FILE, or make them from the page)");
}

void ViewRenderer::attachSurfels(const std::filesystem::path& file) {
  const std::lock_guard lock(mutex_);
  scene_.surfels.emplace(file, scene_.loaded.scene, scene_.loaded.hierarchy, scene_.cacheBytes);
  hasSurfels_ = true;
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
                                      TextureFiltering textures, const ViewRequest& request) {
  return keptRenderer(mode, samples, image, textures, request).render(camera(request));
}

FrameRenderer& ViewRenderer::keptRenderer(RenderMode mode, std::uint32_t samples, FrameImage image,
                                          TextureFiltering textures, const ViewRequest& request) {
  if (mode == RenderMode::Surfels) requireSurfels();
  // A viewer keeps drawing with the BVHs that rays build: each frame is charged its share of a build, as
  // if a second of frames at 30 a second shared it.
  constexpr double kFramesSharingABuild = 30.0;
  LodOptions lod = request.lod;
  lod.bvhBuildFrames = kFramesSharingABuild;
  const SplatMode splat = lod.splat;
  auto kept = std::find_if(kept_.begin(), kept_.end(), [&](const Kept& k) {
    return k.mode == mode && (mode != RenderMode::Surfels || k.splat == splat) && k.samples == samples &&
           k.image == image && k.textures == textures && k.width == request.width && k.height == request.height;
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
        FrameOptions{.mode = mode, .lod = lod, .samples = samples, .image = image, .textures = textures}, request.width,
        request.height, sources);
    kept_.push_back({mode, splat, samples, image, textures, request.width, request.height, std::move(renderer), 0});
    kept = std::prev(kept_.end());
  }
  kept->lastUse = ++uses_;
  if (mode == RenderMode::Surfels) kept->renderer->setLod(lod);
  return *kept->renderer;
}

ViewFrame ViewRenderer::renderComparison(const ViewRequest& request) {
  const auto start = std::chrono::steady_clock::now();
  const RenderMode testMode = hasSurfels() ? RenderMode::Surfels : RenderMode::Embree;
  const FrameResult test = renderFrame(testMode, request.samples, FrameImage::Float, textures_, request);
  const Camera view = camera(request);
  if (reference_.clipFromWorld != view.clipFromWorld() || reference_.width != request.width ||
      reference_.height != request.height) {
    reference_ = {view.clipFromWorld(), request.width, request.height,
                  renderFrame(RenderMode::Embree, kFlipReferenceSamples, FrameImage::Float,
                              TextureFiltering::Anisotropic, request)
                      .image};
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
    frame.rgba8 = differenceRgba8(test.image, reference_.image, kDifferenceGain);  // as pbs eval's sheets show it
  }
  frame.seconds = secondsSince(start);
  return frame;
}

LodDraws ViewRenderer::traverse(const ViewRequest& request) {
  // The surfel frame's own cut: whether rays draw its geometry decides which nodes it descends into.
  return keptRenderer(RenderMode::Surfels, request.samples, FrameImage::Rgba8, textures_, request).cut(camera(request));
}

Framebuffer ViewRenderer::drawWithIds(const LodDraws& draws, const ViewRequest& request) {
  scene_.surfels->load(draws);
  LazyMeshes::Lease meshes;
  if (scene_.meshes) meshes = scene_.meshes->requireDrawnBy(draws.geometryNodes);
  const ChannelMask coverage = request.lod.splat == SplatMode::Blend ? ChannelMask{kChannelCoverage} : 0;
  Framebuffer gbuffer =
      makeFramebuffer(request.width, request.height, kChannelColor | kChannelNormal | kChannelIds | coverage);
  // The rasterizer for the geometry: it writes the ids (rays would draw the same pixels).
  drawLod(scene_.loaded.scene, scene_.loaded.hierarchy, scene_.surfels->surfels(), draws, camera(request), gbuffer,
          request.lod);
  return gbuffer;
}

ViewFrame ViewRenderer::renderSources(const ViewRequest& request) {
  const auto start = std::chrono::steady_clock::now();
  const LodDraws draws = traverse(request);
  const Framebuffer gbuffer = drawWithIds(draws, request);
  const std::unordered_map<std::uint32_t, DrawKind> kinds = kindsOf(draws);
  std::vector<glm::vec4> image = shadeHeadlight(gbuffer, camera(request));
  for (std::size_t i = 0; i < image.size(); ++i) {
    if (!gbuffer.covered(i)) continue;
    const auto kind = kinds.find(gbuffer.ids[i].node);
    if (kind == kinds.end()) continue;
    const glm::vec3 tint = kKindColors[int(kind->second)];
    image[i] = glm::vec4(glm::vec3(image[i]) * 0.45f + tint * 0.55f, image[i].a);
  }
  ViewFrame frame;
  frame.rgba8 = toRgba8(image);
  frame.seconds = secondsSince(start);
  frame.stats.triangles = draws.triangles;
  frame.stats.surfels = draws.surfelCount;
  frame.stats.nodesGeometry = draws.geometryNodes.size();
  frame.stats.nodesSurfels = draws.surfels.size();
  return frame;
}

ViewFrame ViewRenderer::renderPrefix(const ViewRequest& request) {
  const auto start = std::chrono::steady_clock::now();
  requireSurfels();
  const std::uint32_t node = *request.node;
  if (node >= scene_.loaded.scene.nodes.size())
    throw std::invalid_argument("node: the scene has " + std::to_string(scene_.loaded.scene.nodes.size()) + " nodes");
  const SceneSurfels& surfels = scene_.surfels->surfels();
  std::optional<LodDraws::Surfels> whole =
      wholeArrayDraw(scene_.loaded.scene, scene_.loaded.hierarchy, surfels, camera(request), request.lod, node);
  if (!whole) throw std::invalid_argument("node " + std::to_string(node) + ": no surfels to draw from this view");
  // The prefix's own disc (r = √(packing / k)), in pixels as the node's whole draw scales its radius.
  const SplatArray& array = surfels.arrays[whole->array];
  LodDraws::Surfels draw = *whole;
  draw.count = draw.full = std::uint32_t(std::min<std::size_t>(request.prefix, array.size()));
  draw.radius = array.spacing(draw.count);
  draw.pointSize = whole->radius > 0.0 ? whole->pointSize * draw.radius / whole->radius : whole->pointSize;
  LodDraws draws;
  draws.surfels.push_back(draw);
  draws.surfelCount = draw.count;
  const Framebuffer gbuffer = drawWithIds(draws, request);
  ViewFrame frame;
  frame.rgba8 = shadeHeadlightRgba8(gbuffer, camera(request));
  frame.seconds = secondsSince(start);
  frame.stats.surfels = draw.count;
  frame.stats.nodesSurfels = 1;
  return frame;
}

std::vector<NodeDraw> ViewRenderer::nodeDraws(const ViewRequest& request, std::size_t limit) {
  const std::lock_guard lock(mutex_);
  const LodDraws draws = traverse(request);
  const Camera view = camera(request);
  const Scene& scene = scene_.loaded.scene;
  const Hierarchy& hierarchy = scene_.loaded.hierarchy;
  std::unordered_map<std::uint32_t, const LodDraws::Surfels*> prefixes;
  for (const LodDraws::Surfels& draw : draws.surfels) prefixes[draw.node] = &draw;
  std::vector<NodeDraw> nodes;
  for (const auto& [node, kind] : kindsOf(draws)) {
    NodeDraw entry{.node = node, .kind = kind};
    const Bounds& box = hierarchy.worldBounds[node];
    entry.rect = projectedRect(view, box);
    entry.size = std::sqrt(projectedBoxPixels(view, box));
    if (const std::int32_t mesh = scene.nodes[node].mesh; mesh >= 0 && kind != DrawKind::Surfels)
      entry.triangles = scene.meshes[std::size_t(mesh)].triangleCount();
    if (const auto prefix = prefixes.find(node); prefix != prefixes.end()) {
      entry.surfels = prefix->second->count;
      entry.full = prefix->second->full;
    }
    nodes.push_back(entry);
  }
  // Largest first; ties by node, so the list is the same every time.
  std::sort(nodes.begin(), nodes.end(),
            [](const NodeDraw& a, const NodeDraw& b) { return a.size != b.size ? a.size > b.size : a.node < b.node; });
  if (nodes.size() > limit) nodes.resize(limit);
  return nodes;
}

std::optional<std::uint32_t> ViewRenderer::pick(const ViewRequest& request) {
  const std::lock_guard lock(mutex_);
  const Framebuffer gbuffer = drawWithIds(traverse(request), request);
  const std::size_t pixel = std::size_t(request.y) * request.width + request.x;
  if (!gbuffer.covered(pixel)) return std::nullopt;
  return gbuffer.ids[pixel].node;
}

std::optional<ViewFrame> ViewRenderer::render(const ViewRequest& request, const std::function<bool()>& superseded) {
  const std::lock_guard lock(mutex_);
  if (superseded()) return std::nullopt;
  if (request.show == ViewShow::Difference || request.show == ViewShow::Flip) return renderComparison(request);
  if (request.show == ViewShow::Source) return renderSources(request);
  if (request.show == ViewShow::Prefix) return renderPrefix(request);
  const RenderMode mode = request.show == ViewShow::Surfels ? RenderMode::Surfels
                          : request.show == ViewShow::Exact ? RenderMode::Exact
                                                            : RenderMode::Embree;
  const auto start = std::chrono::steady_clock::now();
  FrameResult result = renderFrame(mode, request.samples, FrameImage::Rgba8, textures_, request);
  ViewFrame frame;
  frame.rgba8 = std::move(result.rgba8);
  frame.drawnBy = mode;
  frame.samples = request.samples;
  frame.seconds = secondsSince(start);
  frame.stats = result.stats;
  return frame;
}

}  // namespace pbs::cli
