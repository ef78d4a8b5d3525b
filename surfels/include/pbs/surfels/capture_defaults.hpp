// The capture's defaults, in one place: CaptureOptions starts from them, and so does SurfelFileOptions,
// which records what a file's arrays were captured with.
#pragma once

#include <cstdint>

namespace pbs {

// Pixels along the larger side of a view's box. 384 rather than 512: on the default scene and a billion-triangle
// city (orbit, approach, flythrough) FLIP is the same or lower, and surfelize takes 25-27 % less time
// (docs/evaluation.md, "Capture resolution"); 256 lost 17 % FLIP on the city's far orbit.
inline constexpr std::uint32_t kDefaultCaptureResolution = 384;
inline constexpr std::uint32_t kDefaultCaptureDirections = 8;  // the box-corner diagonals of the paper

}  // namespace pbs
