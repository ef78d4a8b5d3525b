// captureNode: renders a node's subtree from each capture direction and turns covered pixels into surfels.
#include "pbs/surfels/capture.hpp"

#include "pbs/raster/box_view.hpp"
#include "pbs/raster/framebuffer.hpp"
#include "pbs/raster/projected_box.hpp"
#include "pbs/scene/embree_caster.hpp"
#include "pbs/scene/scene_draws.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <functional>
#include <stdexcept>

namespace pbs {
namespace {

// The authors' coverage rule: alpha > 0.1 in RGBA8.
constexpr std::uint8_t kMinCoveredAlpha = 26;

// Pixels are read in groups of this many: most of a view is empty, and a group without a covered pixel
// is then one test of its depths.
constexpr std::size_t kGroup = 8;

// Whether no pixel of [first, first + kGroup) is covered: depth is kClearDepth, +inf, whose bits no other
// value has, so the test is on the bits (a NaN depth counts as covered, as in Framebuffer::covered).
bool noneCovered(const float* depth) {
  constexpr std::uint32_t kClearBits = std::bit_cast<std::uint32_t>(kClearDepth);
  std::uint32_t bits[kGroup];
  std::memcpy(bits, depth, sizeof bits);
  std::uint32_t differs = 0;
  for (std::uint32_t b : bits) differs |= b ^ kClearBits;
  return differs == 0;
}

// `direction` is the one the view looks along. Normals are turned to face it: a one-sided surface seen
// from behind must not keep a normal pointing away from every view that can see it, else a renderer
// could not tell front-facing surfels from back-facing ones. A zero normal stays zero.
// The channels are held in locals: the colour's byte stores may alias anything, and would have every
// pointer reloaded per surfel.
void appendSurfels(const Framebuffer& framebuffer, const glm::vec3& direction, CaptureResult& result) {
  const std::size_t pixels = framebuffer.pixelCount();
  const float* const depth = framebuffer.depth.data();
  const glm::u8vec4* const colors = framebuffer.color.data();
  const glm::vec3* const positions = framebuffer.position.data();
  const glm::vec3* const normals = framebuffer.normal.data();
  std::vector<Surfel>& surfels = result.surfels;
  std::uint64_t seenFromBehind = 0;
  for (std::size_t first = 0; first < pixels; first += kGroup) {
    const std::size_t end = std::min(first + kGroup, pixels);
    if (end - first == kGroup && noneCovered(depth + first)) continue;
    for (std::size_t pixel = first; pixel < end; ++pixel) {
      if (depth[pixel] == kClearDepth || colors[pixel].a < kMinCoveredAlpha) continue;
      const glm::vec3 normal = normals[pixel];
      const bool behind = glm::dot(normal, direction) > 0.0f;
      seenFromBehind += behind;
      // Field by field: a braced Surfel was built on the stack and copied out in 16-byte loads that
      // straddled its smaller stores, a store-forwarding stall per candidate (two thirds of this
      // function's samples).
      Surfel& surfel = surfels.emplace_back();
      surfel.position = positions[pixel];
      surfel.normal = behind ? -normal : normal;
      surfel.color = colors[pixel];
    }
  }
  result.seenFromBehind += seenFromBehind;
}

}  // namespace

std::size_t concurrentCaptureViews(std::size_t views, std::size_t pixelsPerView, int threads) {
  if (threads <= 0) threads = tbb::this_task_arena::max_concurrency();
  const std::size_t fitting = kConcurrentCaptureBytes / std::max<std::size_t>(1, pixelsPerView * kCaptureBytesPerPixel);
  return std::max<std::size_t>(1, std::min({views, std::size_t(std::max(threads, 1)), fitting}));
}

void drawViewsInGroups(std::size_t views, std::size_t group, const std::function<void(std::size_t view)>& drawView,
                       const std::function<void(std::size_t first, std::size_t end)>& afterGroup) {
  group = std::max<std::size_t>(group, 1);
  for (std::size_t first = 0; first < views; first += group) {
    const std::size_t end = std::min(first + group, views);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(first, end, 1), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t v = r.begin(); v < r.end(); ++v) drawView(v);
    });
    if (afterGroup) afterGroup(first, end);
  }
}

double CaptureResult::sidesSeen() const {
  const std::uint64_t front = surfels.size() - seenFromBehind;
  const std::uint64_t larger = std::max(front, seenFromBehind), smaller = std::min(front, seenFromBehind);
  return larger > 0 ? 1.0 + double(smaller) / double(larger) : 1.0;
}

CaptureResult captureBox(const Bounds& box, const CaptureOptions& options, const DrawCaptureView& draw) {
  if (options.resolution == 0) throw std::invalid_argument("capture: resolution must be at least 1");
  const std::vector<glm::dvec3> directions = captureDirections(options.directions);
  CaptureResult result;
  if (box.empty()) return result;
  result.origin = box.center();

  std::vector<Camera> cameras;
  std::size_t pixels = 0;
  for (const glm::dvec3& direction : directions) {
    cameras.push_back(boxViewCamera(box, direction, options.resolution));
    pixels += std::size_t(cameras.back().width) * cameras.back().height;
  }
  // Room for every pixel of every view at once: grown view by view, the candidates were copied about
  // once more and their new pages faulted in again (memcpy and page faults were 15 % of surfelize's
  // samples). The pages past the candidates are never touched.
  result.surfels.reserve(pixels);

  double boxArea = 0.0;
  // A G-buffer per view drawn at once, reused by the views after it, of which only depth is cleared
  // (kCaptureClearedChannels). The views are drawn in groups, then read in order.
  std::size_t largestView = 0;
  for (const Camera& camera : cameras) largestView = std::max<std::size_t>(largestView, camera.width * camera.height);
  const std::size_t group = concurrentCaptureViews(cameras.size(), largestView);
  std::vector<Framebuffer> framebuffers;
  for (std::size_t i = 0; i < group; ++i)
    framebuffers.push_back(makeFramebuffer(0, 0, kCaptureChannels, result.origin));
  const auto drawView = [&](std::size_t v) {
    Framebuffer& framebuffer = framebuffers[v % group];
    resizeFramebuffer(framebuffer, cameras[v].width, cameras[v].height);
    clearFramebuffer(framebuffer, kCaptureClearedChannels);
    draw(cameras[v], framebuffer);
  };
  const auto readViews = [&](std::size_t first, std::size_t end) {
    for (std::size_t v = first; v < end; ++v) {
      const Framebuffer& framebuffer = framebuffers[v % group];
      if (options.onView) options.onView(result.views, cameras[v], framebuffer);
      const std::size_t before = result.surfels.size();
      appendSurfels(framebuffer, glm::vec3(directions[v]), result);
      result.coveredPixels += result.surfels.size() - before;
      boxArea += projectedBoxPixels(cameras[v], box);
      ++result.views;
    }
  };
  drawViewsInGroups(cameras.size(), group, drawView, readViews);
  result.boxPixels = static_cast<std::uint64_t>(std::llround(boxArea));
  const double denominator = std::max(boxArea, double(result.coveredPixels));
  result.coverage = denominator > 0.0 ? double(result.coveredPixels) / denominator : 0.0;
  return result;
}

CaptureResult captureNode(const Scene& scene, const Hierarchy& hierarchy, std::uint32_t node,
                          const CaptureOptions& options) {
  if (node >= scene.nodes.size()) throw std::invalid_argument("captureNode: node index out of range");
  const Bounds& box = hierarchy.worldBounds[node];
  if (box.empty()) return captureBox(box, options, {});

  const std::vector<std::uint32_t> nodes = subtreeNodes(scene, node);
  if (options.backend == CaptureOptions::Backend::Embree) {
    // Built once for all views: the BVH build is the Embree backend's main fixed cost.
    const EmbreeScene embree(scene, hierarchy, nodes);
    return captureBox(box, options,
                      [&](const Camera& camera, Framebuffer& framebuffer) { embree.render(camera, framebuffer); });
  }
  return captureBox(box, options, [&](const Camera& camera, Framebuffer& framebuffer) {
    drawNodeTriangles(scene, hierarchy, nodes, camera, framebuffer, TriangleOptions{.cullBackFaces = false},
                      options.meshClosures);
  });
}

}  // namespace pbs
