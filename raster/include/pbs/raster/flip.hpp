// LDR-FLIP, NVIDIA's perceptual difference between two display-referred sRGB pictures (Andersson et al., HPG 2020).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <numbers>
#include <span>
#include <vector>

namespace pbs {

// The paper's observer: 0.7 m from a 0.7 m wide screen 3840 pixels across, 3840·π/180 ≈ 67.02 pixels
// per degree of visual angle (the paper rounds it to 67; NVIDIA's tool uses this value).
inline constexpr double kDefaultPixelsPerDegree = 3840.0 * std::numbers::pi / 180.0;
// Larger values are refused: the filter kernels grow with the pixels per degree (about 0.14 pixels
// of radius per unit), and beyond this they would be thousands of pixels wide.
inline constexpr double kMaxPixelsPerDegree = 10000.0;

struct FlipResult {
  double mean = 0.0;       // mean of the per-pixel values; 0 for an empty image
  double median = 0.0;     // plain median (for an even count the mean of the two middle values); 0 if empty
  double max = 0.0;        // 0 if empty
  std::vector<float> map;  // per-pixel FLIP in [0, 1], row-major, only when asked for
};

// LDR-FLIP of `test` against `reference`, each width·height sRGB display values (row-major), as the
// paper defines it:
//   - colour: sRGB → linear → XYZ → YCxCz; each opponent channel filtered with the paper's
//     contrast-sensitivity functions (Gaussians in degrees of visual angle, 2-D kernels normalised to
//     sum 1, one radius for all: ⌈3·√(0.04/2π²)·pixelsPerDegree⌉); back to linear RGB clamped to
//     [0, 1] → CIELAB (D65) → Hunt-adjusted → HyAB distance, raised to 0.7 and remapped to [0, 1]
//     against the green-to-blue distance (pc 0.4, pt 0.95);
//   - features: edges (first Gaussian derivative) and points (second derivative) of the unfiltered
//     luminance, σ = 0.041 degrees, radius ⌈3σ⌉; ΔEf = (max(|Δedge|, |Δpoint|) / √2)^0.5;
//   - per pixel FLIP = ΔEc^(1 − ΔEf).
// Borders are clamp-to-edge (outside pixels repeat the nearest edge pixel), as in NVIDIA's tool.
// Inputs are clamped to [0, 1] first, NaN counting as 0 (+∞ as 1); alpha, if any, must already be
// composited. Per-pixel values agree with NVIDIA's implementation to about 1e-4. Pixels farther than
// the kernel radius from every difference score exactly 0 (identical images everywhere); swapping
// reference and test gives the same bits.
// Throws std::invalid_argument when either span is not width·height long, or pixelsPerDegree is not
// a finite number in (0, kMaxPixelsPerDegree]. An empty image gives all zeros.
// Runs in parallel by rows; the result is bit-identical for any thread count.
FlipResult computeFlip(std::span<const glm::vec3> reference, std::span<const glm::vec3> test, std::uint32_t width,
                       std::uint32_t height, double pixelsPerDegree = kDefaultPixelsPerDegree, bool keepMap = false);

// A FLIP map as a picture, RGBA8 (4 bytes a value, alpha 255): black for 0 through violet, red and
// orange to pale yellow for 1, every channel non-decreasing so that brightness rises with the error.
// Values are clamped to [0, 1], NaN counting as 0.
std::vector<std::uint8_t> flipMapRgba8(std::span<const float> map);

}  // namespace pbs
