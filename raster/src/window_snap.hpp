// Snapping a clip-space vertex to the 1/256-pixel window grid, exactly as triangles.hpp states it.
#pragma once

#include "triangle_records.hpp"

#include "pbs/raster/camera.hpp"

#include <cmath>
#include <cstdint>

namespace pbs::triangles {

struct WindowVertex {
  std::int32_t x, y;  // 1/256 pixel
  double depth;       // window depth
  double invW;        // for perspective-correct interpolation
};

// The caller guarantees the guard band (|x_w|, |y_w| ≤ 2^21), so the snapped values fit int32.
inline WindowVertex snapToWindow(const Camera& camera, const glm::dvec4& clip) {
  const glm::dvec3 window = windowFromClip(camera, clip);
  const double scale = double(kSubpixelScale);
  return {std::int32_t(std::floor(window.x * scale + 0.5)), std::int32_t(std::floor(window.y * scale + 0.5)),
          window.z, clip.w == 1.0 ? 1.0 : 1.0 / clip.w};
}

}  // namespace pbs::triangles
