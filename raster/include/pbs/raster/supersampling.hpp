// Supersampling for the exact renderers: a fixed pattern of sub-pixel sample positions, the camera
// that samples at one of them, and the box-filter resolve of the accumulated samples.
#pragma once

#include "pbs/raster/camera.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace pbs {

// Sample counts the renderers accept: 1 (the pixel centre) and the squares 4, 16, 64, 256.
bool isSupportedSampleCount(std::uint32_t samples);

// The sample positions within a pixel, in [0, 1)² (x right, y down, as window coordinates), for a
// supported count n = s². A rotated grid with one sample in each of the n columns and n rows of an
// n × n grid (n-rooks): sample (i, j), 0 ≤ i, j < s, sits at
//   x = (i·s + j + 0.5) / n,   y = (j·s + (s − 1 − i) + 0.5) / n,
// so its neighbours lie (s, −1)/n and (1, s)/n away: a square lattice turned by atan(1/s) (26.6° for
// 4, the classic rotated-grid pattern; 14.0° for 16, 7.1° for 64), which resolves near-horizontal and
// near-vertical edges into n levels where an axis-aligned grid gives s. n = 1 is the centre
// (0.5, 0.5). Fixed, so that every run and every renderer samples the same places.
std::vector<glm::dvec2> subpixelSamples(std::uint32_t samples);

// The camera whose pixel centres fall at `sample` (a position from subpixelSamples) of `camera`'s
// pixels: the projection is shifted by (sample − 0.5) pixels in clip space, the view is unchanged, and
// the sample spacing is that of `samples` per pixel (1/√samples), so textures are filtered over one
// sample's share of a pixel. Both renderers take a camera, so both sample the same positions through
// this one function.
Camera subpixelCamera(const Camera& camera, const glm::dvec2& sample, std::uint32_t samples);

// Sums of shaded samples per pixel, premultiplied (background adds (0, 0, 0, 0)), and their count.
struct SampleSums {
  std::vector<glm::vec4> sums;
  std::uint32_t samples = 0;
};

// The box filter: each pixel is the mean of its samples, with alpha the fraction of them that hit a
// surface and colour un-premultiplied (straight, as pbs writes images): rgb = Σ rgb / Σ alpha where
// some sample hit, (0, 0, 0, 0) where none did. Bit-identical for any thread count.
std::vector<glm::vec4> resolveSamples(const SampleSums& sums);

}  // namespace pbs
