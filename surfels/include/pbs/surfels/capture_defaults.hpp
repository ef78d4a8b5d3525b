// The capture's defaults, in one place: CaptureOptions starts from them, and so does SurfelFileOptions,
// which records what a file's arrays were captured with.
#pragma once

#include <cstdint>

namespace pbs {

inline constexpr std::uint32_t kDefaultCaptureResolution = 512;  // pixels along the larger side of a view's box
inline constexpr std::uint32_t kDefaultCaptureDirections = 8;    // the box-corner diagonals of the paper

}  // namespace pbs
