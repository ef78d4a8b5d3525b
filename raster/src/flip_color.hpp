// FLIP's colour pipeline: opponent planes, contrast-sensitivity filtering and the per-pixel colour error ΔEc.
#pragma once

#include "flip_filters.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <span>

namespace pbs::flip {

// An image in YCxCz, one plane a channel.
struct OpponentPlanes {
  Plane achromatic;  // Y' = 116·Y/Yn − 16
  Plane redGreen;    // Cx
  Plane blueYellow;  // Cz
};

// sRGB display values (clamped to [0, 1], NaN as 0) to YCxCz planes; parallel by rows.
OpponentPlanes toOpponentPlanes(std::span<const glm::vec3> srgb, std::uint32_t width, std::uint32_t height);

// The contrast-sensitivity functions as separable kernels for one viewing distance. The blue-yellow
// one is a sum of two Gaussians, each separable but not their sum: it is filtered with each and
// the results blended, with the shares the 2-D terms have in the normalised 2-D kernel.
struct ColorFilters {
  HalfKernel achromatic;
  HalfKernel redGreen;
  HalfKernel blueYellowBroad;   // b = 0.04
  HalfKernel blueYellowNarrow;  // b = 0.025
  float broadShare = 0.0f;      // blue-yellow = narrow + broadShare·(broad − narrow)
  std::uint32_t radius = 0;     // shared by all four
};

ColorFilters makeColorFilters(double pixelsPerDegree);

// ΔEc in [0, 1] for rows [yBegin, yEnd), written to out (row yBegin first, width values a row).
void colorErrorRows(const ColorFilters& filters, const OpponentPlanes& reference, const OpponentPlanes& test,
                    std::uint32_t yBegin, std::uint32_t yEnd, float* out);

}  // namespace pbs::flip
