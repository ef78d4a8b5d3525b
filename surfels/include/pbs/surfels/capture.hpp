// Capture of a node's initial surfels: orthographic G-buffer views around the node's box, one
// surfel per covered pixel, and the coverage estimate the renderer scales counts with (paper, Sec. 2.1).
#pragma once

#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/mesh_closure.hpp"
#include "pbs/scene/scene.hpp"

#include "pbs/raster/camera.hpp"
#include "pbs/raster/framebuffer.hpp"
#include "pbs/surfels/capture_defaults.hpp"
#include "pbs/surfels/surfel.hpp"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace pbs {

struct CaptureOptions {
  std::uint32_t resolution = kDefaultCaptureResolution;  // pixels along the larger side of each view's projected box
  // 8: the box-corner diagonals (±1, ±1, ±1) of the paper; any other count: a spherical Fibonacci
  // set (deterministic, evenly spread), e.g. 16 or 32.
  std::uint32_t directions = kDefaultCaptureDirections;
  enum class Backend { Raster, Embree } backend = Backend::Raster;
  // Per mesh (or none): meshClosure. A capture view looks at the node's box from outside, so it can see the faces
  // of a closed mesh that face its inside only where the boxes of the mesh's holes project; the Raster backend
  // leaves them out everywhere else (pbs surfelize default in 0.85× the time on one thread). Embree draws them all.
  std::span<const MeshClosure> meshClosures{};
  // Called with every view's camera and G-buffer right after it is rendered (for pictures and
  // debugging: `pbs capture` writes them as images); nothing is kept for it otherwise. Only depth
  // is cleared between views: colour, position and normal hold this view's values where depth says
  // a pixel is covered (Framebuffer::covered), and anything elsewhere.
  std::function<void(std::uint32_t view, const Camera& camera, const Framebuffer& gbuffer)> onView{};
};

struct CaptureResult {
  glm::dvec3 origin{0.0};       // the centre of the node's world box
  std::vector<Surfel> surfels;  // views in order, each view's pixels in row-major order
  // Covered pixels over the projected box area, both summed over the views. The projected box area
  // of a view is the area, in pixels, of the convex hull of the box's 8 projected corners (its
  // silhouette). The denominator is max(box area, covered pixels): covered pixel centres may
  // slightly outnumber a silhouette's continuous area, and a flat box seen edge-on has area ~0, so
  // coverage stays in [0, 1] and is 0 (never a division by zero) when nothing is covered.
  double coverage = 0.0;
  std::uint64_t coveredPixels = 0;
  std::uint64_t boxPixels = 0;  // the summed projected box area, rounded to whole pixels
  std::uint32_t views = 0;      // 0 for a node whose subtree draws nothing (an empty box)
  // Of the surfels, those seen from behind their normal (turned to face their view): about none for a
  // closed mesh, about half for an open sheet seen from both sides (a terrain, a wall).
  std::uint64_t seenFromBehind = 0;

  // How many sides of its surface the captures saw, 1 to 2: 1 + the smaller share of surfels seen from
  // one side over the larger (so a mesh wound inside out counts once, as one wound outward does).
  double sidesSeen() const;
};

// The view directions (unit vectors the cameras look along) for `count` views; see
// CaptureOptions::directions. Throws std::invalid_argument for 0.
std::vector<glm::dvec3> captureDirections(std::uint32_t count);

// The capture's G-buffer: colour, position and normal beside depth (kCaptureChannels), of which each
// view clears depth alone (kCaptureClearedChannels: none besides it). The surfels and the pictures of
// CaptureOptions::onView read the other channels only where depth says a pixel is covered, and clearing
// them would be 28 of the 32 bytes a pixel.
inline constexpr ChannelMask kCaptureChannels = kChannelColor | kChannelPosition | kChannelNormal;
inline constexpr ChannelMask kCaptureClearedChannels = 0;

inline constexpr std::size_t kCaptureBytesPerPixel = framebufferBytesPerPixel(kCaptureChannels);

// How many of a capture's `views` are drawn at once, each on its own thread into its own G-buffer of
// `pixelsPerView` pixels: as many as `threads` (0: the current arena's), within kConcurrentCaptureBytes of
// G-buffers, at least one. One view's stages are short parallel loops over data that one thread wrote and another
// reads (the setup's and the bins' work grows by a third to double on a second thread); views side by side keep each
// thread on its own view's data. The surfels are the same either way.
inline constexpr std::size_t kConcurrentCaptureBytes = std::size_t(64) << 20;
std::size_t concurrentCaptureViews(std::size_t views, std::size_t pixelsPerView, int threads = 0);

// Draws views [0, views) `group` at a time: `drawView(view)` for each view of a group on a thread of its own (into
// G-buffer view % group), then `afterGroup(first, end)` on the calling thread for the group's views [first, end).
void drawViewsInGroups(std::size_t views, std::size_t group, const std::function<void(std::size_t view)>& drawView,
                       const std::function<void(std::size_t first, std::size_t end)>& afterGroup = {});

// Draws one capture view: fills the G-buffer (colour, position relative to the box centre, normal) as
// seen by `camera`.
// Called for several views at once (concurrentCaptureViews), each with its own G-buffer.
using DrawCaptureView = std::function<void(const Camera& camera, Framebuffer& gbuffer)>;

// The capture of `box` with whatever `draw` puts in each view: the views, surfels and coverage of
// captureNode, for captures that draw something other than a subtree's triangles (a node's children's
// surfels, say). options.backend is not used. A pixel gives a surfel when it is covered and its colour
// alpha exceeds 0.1 (the authors' rule: fully transparent texels make no surfels). Its normal is the
// G-buffer's, negated where needed to face the view: dot(normal, view direction) ≤ 0, so the back of
// a one-sided surface gets surfels facing away from its front ones (a zero normal stays zero).
CaptureResult captureBox(const Bounds& box, const CaptureOptions& options, const DrawCaptureView& draw);

// Captures `node`'s whole subtree (world transforms applied; nothing outside the subtree drawn), one
// orthographic view per direction fitted to hierarchy.worldBounds[node], faces never culled.
// `hierarchy` comes from analyzeHierarchy(scene). The result does not depend on the thread count.
// Throws std::invalid_argument for a node out of range, resolution 0 or directions 0.
CaptureResult captureNode(const Scene& scene, const Hierarchy& hierarchy, std::uint32_t node,
                          const CaptureOptions& options);

}  // namespace pbs
