// Separable filtering for FLIP: 1-D kernels even or odd about their centre, run down the columns of a
// plane and along clamp-padded rows.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace pbs::flip {

// One channel of an image, row-major. Not zero-filled: whoever makes one writes every value (in
// parallel, so that its pages are first touched by the threads that use them).
struct Plane {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::unique_ptr<float[]> values;  // width·height

  Plane() = default;
  Plane(std::uint32_t width, std::uint32_t height)
      : width(width), height(height), values(std::make_unique_for_overwrite<float[]>(std::size_t(width) * height)) {}
  const float* row(std::uint32_t y) const { return values.get() + std::size_t(y) * width; }
  float* row(std::uint32_t y) { return values.get() + std::size_t(y) * width; }
};

// How the taps on either side of a kernel's centre relate. The centre tap is implied by the shape
// rather than stored, and each tap weighs a difference with the centre value: a flat signal then
// filters exactly, to itself when smoothing and to 0 under a derivative, whatever the rounding of
// the weights (so flat regions, and identical ones, give exactly zero error).
enum class KernelShape {
  smoothing,  // even, sums to 1:  out = c + Σk w[k]·(v[−k] + v[+k] − 2c)
  curvature,  // even, sums to 0:  out =     Σk w[k]·(v[−k] + v[+k] − 2c)
  slope,      // odd:              out =     Σk w[k]·(v[+k] − v[−k])
};

// A kernel by the taps on its positive side: weights[k − 1] is the tap at offset +k, k = 1 … radius.
struct HalfKernel {
  KernelShape shape = KernelShape::smoothing;
  std::vector<float> weights;

  std::uint32_t radius() const { return std::uint32_t(weights.size()); }
};

// A row with `padding` copies of its first value before it and of its last after it: clamp-to-edge
// borders without a branch in the filter loops.
struct PaddedRow {
  std::uint32_t width = 0;
  std::uint32_t padding = 0;
  std::vector<float> values;  // padding + width + padding

  PaddedRow(std::uint32_t width, std::uint32_t padding);
  void assign(const float* row);
  const float* begin() const { return values.data() + padding; }  // the row's first pixel
};

// out[x], x < plane.width: `kernel` applied down column x around row y; rows beyond the top and
// bottom are the first and last row.
void filterDown(const Plane& plane, std::uint32_t y, const HalfKernel& kernel, float* out);

// out[x], x < row.width: `kernel` applied along the row; its padding must be at least the radius.
void filterAlong(const PaddedRow& row, const HalfKernel& kernel, float* out);

}  // namespace pbs::flip
