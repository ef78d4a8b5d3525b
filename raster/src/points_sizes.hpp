// The drawn sizes of points (points.hpp: pointSize × factor, clamped, 0 for none): per block, and the largest.
#pragma once

#include "pbs/raster/points.hpp"

#include <cstddef>

namespace pbs::points {

// The drawn sizes of points [first, first + count) of a set; `smallest` as splatSize takes it.
void drawnSizes(const PointSet& set, float smallest, std::size_t first, std::size_t count, float* sizes);

// The largest drawn size in a set (0 when none draws), which bounds how many tiles a splat can overlap.
float largestDrawnSize(const PointSet& set, float smallest);

}  // namespace pbs::points
