// One surfel's screen footprint for blended splatting (blended_splats.hpp): its projected elliptical
// Gaussian, depth plane, tolerance and coverage amplitude, set up once and read by every pixel it touches.
#pragma once

#include "pbs/raster/blended_splats.hpp"
#include "pbs/raster/simd_clones.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace pbs::blend {

// Mahalanobis distance² at which the kernel is cut off (the disc's rim: its radius is 2σ). A footprint
// narrower than that reaches at least kMinReach pixels along its axes, so that some pixel centre always
// falls inside it (none lies more than √½ from any point).
inline constexpr float kCutoff = 4.0f;
inline constexpr float kMinReach = 0.75f;

// exp(−q/2) for 0 ≤ q ≤ kMaxCutoff, interpolated in a table (relative error below 2e-4): the kernel is
// evaluated a few times per pixel a splat touches, where a libm call dominated. Deterministic like any
// table; q outside the range gives the end values. Inline, so that SIMD clones of its callers inline it.
inline constexpr float kMaxCutoff = 8.0f;
inline constexpr int kKernelSteps = 32;  // table entries per unit of q
struct KernelTable {
  KernelTable();
  std::array<float, std::size_t(kMaxCutoff) * kKernelSteps + 2> values;
};
extern const KernelTable kKernel;
PBS_CLONE_INLINE float kernelWeight(float q) {
  const float t = std::clamp(q, 0.0f, kMaxCutoff) * float(kKernelSteps);
  const int i = int(t);  // 0 … kMaxCutoff · kKernelSteps: a signed conversion is one instruction
  const float f = t - float(i);
  return kKernel.values[std::size_t(i)] + f * (kKernel.values[std::size_t(i) + 1] - kKernel.values[std::size_t(i)]);
}

struct Footprint {
  float x, y;                    // window position of the centre
  float depth;                   // window depth of the centre
  float tolerance;               // window depth of one disc radius along the view ray
  float conicA, conicB, conicC;  // q = A dx² + 2B dx dy + C dy², the inverse covariance
  float depthDx, depthDy;        // window depth change per pixel along the disc's plane
  float depthReach;              // the plane's depth change is clamped to the disc's own depth extent
  float cutoff;                  // Mahalanobis distance² of the footprint's edge: kCutoff or more
  float amplitude;               // coverage at q = 0
  glm::vec3 normal;              // world, unit, facing the eye
  glm::u8vec4 color;
  std::uint16_t x0, y0, x1, y1;  // pixel rectangle [x0, x1) × [y0, y1), clipped to the viewport
  std::uint32_t set, index;      // for the ids channel

  // Mahalanobis distance² of pixel (px, py)'s centre.
  [[gnu::always_inline]] float distance(int px, int py) const {
    const float dx = float(px) + 0.5f - x, dy = float(py) + 0.5f - y;
    return conicA * dx * dx + 2.0f * conicB * dx * dy + conicC * dy * dy;
  }
  [[gnu::always_inline]] float weight(float q) const { return kernelWeight(q); }
  [[gnu::always_inline]] float depthAt(int px, int py) const {
    const float dx = float(px) + 0.5f - x, dy = float(py) + 0.5f - y;
    const float change = depthDx * dx + depthDy * dy;
    return depth + (change < -depthReach ? -depthReach : change > depthReach ? depthReach : change);
  }
};

// Projects the sets' surfels; per set, the transforms and the eye in its object frame are computed once.
class FootprintProjector {
 public:
  FootprintProjector(const Camera& camera, const SurfelSplatSet& set, std::uint32_t setIndex,
                     const BlendOptions& options);

  // Projects surfels [first, first + count) of the set into `out`, those culled (facing away, outside the
  // depth range, off screen, not finite) left out; returns how many were written.
  std::size_t projectRange(std::size_t first, std::size_t count, Footprint* out) const;

  // projectRange's body for surfels [first, first + count), count ≤ kProjectBatch (inlined into each SIMD clone
  // of its caller): footprints into `out`, in surfel order; returns how many.
  std::size_t projectBatch(std::size_t first, std::size_t count, Footprint* out) const;
  static constexpr std::size_t kProjectBatch = 64;

 private:
  const SurfelSplatSet& set_;
  std::uint32_t setIndex_;
  glm::dmat4 windowFromObject_;
  glm::dmat3 normalFromObject_;
  glm::dvec3 eye_;  // in the set's object frame: the eye (perspective) or the direction to it (orthographic)
  bool eyeIsPoint_ = true;
  double backFaceCosine_;
  double areaGain_;  // gain × the area a surfel stands for ÷ radius²: amplitude × weights ÷ |det| of the disc's map
  int width_, height_;
};

}  // namespace pbs::blend
