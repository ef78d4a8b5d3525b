// How far one picture is from another: RMSE, PSNR, luminance SSIM and the holes one leaves in the other.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <limits>
#include <vector>

namespace pbs {

// Float RGBA, row-major, row 0 at the top, as renders are stored: colour, and alpha 0 where nothing
// was drawn (background) and 1 where a surface was. Alpha < 0.5 counts as background.
struct RgbaImage {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<glm::vec4> pixels;  // width·height

  std::size_t pixelCount() const { return std::size_t(width) * height; }
};

inline constexpr float kSurfaceAlpha = 0.5f;  // alpha at or above this is surface, below it background

// Every pixel counts, background included, with the colour it stores (renders store black behind
// alpha 0): RGB is compared as stored, unpremultiplied, alpha only decides background or surface.
struct ImageDifference {
  double rmse = 0.0;  // root mean square difference over R, G, B of all pixels, in 0..1 units
  // 10·log10(1 / mse) with peak 1 (HDR values above 1 are not rescaled); +infinity when rmse is 0.
  double psnr = std::numeric_limits<double>::infinity();
  // Mean SSIM (Wang et al. 2004) of the luminance Y = 0.2126 R + 0.7152 G + 0.0722 B: Gaussian
  // 11×11 window, σ = 1.5, over the windows that lie wholly inside the image (a side shorter than 11
  // uses the whole side), C1 = 0.01², C2 = 0.03². 1 for identical images.
  double ssim = 1.0;
  // holes / surfaceB: of the pixels where B has surface, the fraction A leaves background; 0 when
  // B has none.
  double holeFraction = 0.0;
  std::uint64_t pixels = 0;    // width·height
  std::uint64_t surfaceA = 0;  // pixels with alpha ≥ 0.5 in A
  std::uint64_t surfaceB = 0;  // … in B
  std::uint64_t holes = 0;     // pixels background in A and surface in B
};

// Compares A with B, which must be the same size (else throws std::invalid_argument). Bit-identical
// results for any thread count: SSIM runs in parallel by rows and sums its rows in order.
ImageDifference compareImages(const RgbaImage& a, const RgbaImage& b);

// The luminance SSIM of compareImages on its own.
double luminanceSsim(const RgbaImage& a, const RgbaImage& b);

}  // namespace pbs
