// Snapping a clip-space vertex to the 1/256-pixel window grid, exactly as triangles.hpp states it.
#pragma once

#include "triangle_records.hpp"

#include "pbs/raster/camera.hpp"
#include "pbs/raster/framebuffer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace pbs::triangles {

struct WindowVertex {
  std::int32_t x, y;  // 1/256 pixel
  double depth;       // window depth
  double invW;        // for perspective-correct interpolation
};

// windowFromClip (camera.cpp) with the same operations in the same order, so bit-identical, but
// inlined: a call per vertex cost a tenth of the projection, and the vertex loops are compiled
// for AVX2 as well (simd_clones.hpp), which a call to camera.cpp would leave out.
inline glm::dvec3 inlineWindowFromClip(const Camera& camera, const glm::dvec4& clip) {
  const glm::dvec3 ndc = clip.w == 1.0 ? glm::dvec3(clip) : glm::dvec3(clip) / clip.w;
  return {(ndc.x + 1.0) * camera.width / 2.0, (1.0 - ndc.y) * camera.height / 2.0, (ndc.z + 1.0) / 2.0};
}

// The caller guarantees the guard band (|x_w|, |y_w| ≤ 2^21), so the snapped values fit int32.
inline WindowVertex snapToWindow(const Camera& camera, const glm::dvec4& clip) {
  const glm::dvec3 window = inlineWindowFromClip(camera, clip);
  const double scale = double(kSubpixelScale);
  return {std::int32_t(std::floor(window.x * scale + 0.5)), std::int32_t(std::floor(window.y * scale + 0.5)), window.z,
          clip.w == 1.0 ? 1.0 : 1.0 / clip.w};
}

// The pixels whose centres 256·p + 128 lie within a box of snapped positions, within the viewport;
// empty where the box holds no pixel centre. Snapped positions lie within ±2^29 (the guard band),
// so int32 holds the sums.
struct PixelBox {
  std::int32_t x0, y0, x1, y1;
  bool empty() const { return x0 > x1 || y0 > y1; }
};

inline PixelBox pixelBox(const Framebuffer& framebuffer, std::int32_t minX, std::int32_t minY, std::int32_t maxX,
                         std::int32_t maxY) {
  constexpr std::int32_t half = kSubpixelScale / 2, up = kSubpixelScale - 1;
  return {std::max(0, (minX - half + up) >> kSubpixelBits), std::max(0, (minY - half + up) >> kSubpixelBits),
          std::min(std::int32_t(framebuffer.width) - 1, (maxX - half) >> kSubpixelBits),
          std::min(std::int32_t(framebuffer.height) - 1, (maxY - half) >> kSubpixelBits)};
}

}  // namespace pbs::triangles
