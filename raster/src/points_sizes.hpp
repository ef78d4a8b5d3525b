// The drawn sizes of points (points.hpp: pointSize × factor, clamped, 0 for none): per block, and the largest.
#pragma once

#include "pbs/raster/points.hpp"

#include <cstddef>

namespace pbs::points {

// The drawn sizes of points [first, first + count) of a set.
void drawnSizes(const PointSet& set, std::size_t first, std::size_t count, float* sizes);

// The largest drawn size in a set (0 when none draws), which bounds how many tiles a splat can overlap.
float largestDrawnSize(const PointSet& set);

}  // namespace pbs::points
