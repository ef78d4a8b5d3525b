// Drawing point splats (surfels) into a Framebuffer: squares or discs of a size in pixels.
#pragma once

#include "pbs/raster/camera.hpp"
#include "pbs/raster/framebuffer.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <span>

namespace pbs {

struct PointSet {
  std::span<const glm::vec3> positions{};  // object frame
  std::span<const glm::vec3> normals{};    // needed only for the normal channel
  std::span<const glm::u8vec4> colors{};   // needed only for the colour channel
  std::span<const float> sizeFactors{};    // optional: per-point multiplier of pointSize
  glm::dmat4 worldFromObject{1.0};
  float pointSize = 1.0f;  // pixels: side of the square, or diameter of the disc
  std::uint32_t nodeId = 0;
  std::uint32_t instanceId = 0;  // PixelIds::primitive is the point's index in its set
};

struct PointOptions {
  bool round = false;  // discs instead of squares
  // Sizes below 1 pixel drawn as they are: such a point covers a pixel only where the pixel's centre
  // lies inside it, as a triangle would, so tiny points sample sub-pixel geometry without inflating it.
  // Off, they draw as 1 pixel (GL's minimum point size).
  bool subPixel = false;
};

// Each point is projected like a triangle vertex (camera.hpp); points outside the near/far range
// are dropped. Size s = pointSize × factor: s ≤ 0 or non-finite draws nothing; 0 < s < 1 draws
// as 1 pixel (as GL clamps to its minimum point size) unless PointOptions::subPixel; s > 4096 draws
// as 4096. A point covers the pixels whose centres lie in [x − s/2, x + s/2) × [y − s/2, y + s/2)
// (a square), or strictly within s/2 of (x, y) (a disc, plus the pixel holding the point unless
// subPixel). Its depth is the
// centre's. The nearest point wins; equal depths go to the earlier point (set order, then index),
// so the image depends neither on the thread count nor on scheduling.
void drawPoints(Framebuffer& framebuffer, const Camera& camera, std::span<const PointSet> sets,
                const PointOptions& options = {});

}  // namespace pbs
