// Capture of a node's initial surfels: orthographic G-buffer views around the node's box, one
// surfel per covered pixel, and the coverage estimate the renderer scales counts with (paper, Sec. 2.1).
#pragma once

#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/scene.hpp"

#include "pbs/raster/camera.hpp"
#include "pbs/raster/framebuffer.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <vector>

namespace pbs {

struct Surfel {
  glm::vec3 position;  // relative to CaptureResult::origin, so far-from-origin nodes keep their digits
  glm::vec3 normal;    // world-space unit normal of the surface as stored (not flipped toward the view)
  glm::u8vec4 color;   // base colour: material factor × texture where the material has one
};

struct CaptureOptions {
  std::uint32_t resolution = 512;  // pixels along the larger side of each view's projected box
  // 8: the box-corner diagonals (±1, ±1, ±1) of the paper; any other count: a spherical Fibonacci
  // set (deterministic, evenly spread), e.g. 16 or 32.
  std::uint32_t directions = 8;
  enum class Backend { Raster, Embree } backend = Backend::Raster;
  // Called with every view's camera and G-buffer right after it is rendered (for pictures and
  // debugging: `pbs capture` writes them as images); nothing is kept for it otherwise.
  std::function<void(std::uint32_t view, const Camera& camera, const Framebuffer& gbuffer)> onView{};
};

struct CaptureResult {
  glm::dvec3 origin{0.0};  // the centre of the node's world box
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
};

// The view directions (unit vectors the cameras look along) for `count` views; see
// CaptureOptions::directions. Throws std::invalid_argument for 0.
std::vector<glm::dvec3> captureDirections(std::uint32_t count);

// Captures `node`'s whole subtree (world transforms applied; nothing outside the subtree drawn), one
// orthographic view per direction fitted to hierarchy.worldBounds[node], faces never culled.
// `hierarchy` comes from analyzeHierarchy(scene). The result does not depend on the thread count.
// Throws std::invalid_argument for a node out of range, resolution 0 or directions 0.
CaptureResult captureNode(const Scene& scene, const Hierarchy& hierarchy, std::uint32_t node,
                          const CaptureOptions& options);

}  // namespace pbs
