// How far one picture is from another: PSNR over the whole image and its foreground, luminance SSIM,
// FLIP, the holes and bloat of one's coverage against the other's, and pass/fail limits on them.
#pragma once

#include "pbs/raster/flip.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace pbs {

// Float RGBA, row-major, row 0 at the top, as renders are stored: straight (not premultiplied) colour,
// and alpha the pixel's coverage: 0 where nothing was drawn (background), 1 where a surface covers it.
struct RgbaImage {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<glm::vec4> pixels;  // width·height

  std::size_t pixelCount() const { return std::size_t(width) * height; }
};

// How the two pictures are seen: both composited over one background, by an observer at a distance.
struct CompareOptions {
  glm::vec3 background{1.0f};                        // straight colour over it: rgb·α + background·(1 − α)
  double pixelsPerDegree = kDefaultPixelsPerDegree;  // FLIP's observer (flip.hpp)
  bool flip = true;                                  // FLIP is most of a comparison's time; off: its fields stay 0
  bool keepFlipMap = false;                          // keep FLIP's per-pixel values in ImageDifference::flipMap
};

// A compared with B (the reference). Coverage is alpha (clamped to [0, 1], NaN as 0): 0 or 1 at one
// sample per pixel, the fraction of samples that hit a surface when supersampled. A NaN or infinite
// colour component counts as 0.
struct ImageDifference {
  // Over the whole composited image, background included: R, G, B in 0..1 units, peak 1 (HDR values
  // above 1 are not rescaled); psnr +infinity when rmse is 0.
  double rmse = 0.0;
  double psnr = std::numeric_limits<double>::infinity();
  // The same over the foreground: the pixels either image covers (alpha > 0). A frame's background,
  // most of its pixels, is shared and would dilute the error, so this is the one to read.
  double foregroundRmse = 0.0;
  double foregroundPsnr = std::numeric_limits<double>::infinity();
  std::uint64_t foregroundPixels = 0;
  // Mean SSIM (Wang et al. 2004) of the composited luminance Y = 0.2126 R + 0.7152 G + 0.0722 B:
  // Gaussian 11×11 window, σ = 1.5, over the windows that lie wholly inside the image (a side shorter
  // than 11 uses the whole side), C1 = 0.01², C2 = 0.03². 1 for identical images.
  double ssim = 1.0;
  // LDR-FLIP (flip.hpp) of A against B, composited and clamped to [0, 1]: mean, median and largest
  // per-pixel value over the whole image, and the mean over the foreground (0 when there is none).
  double flipMean = 0.0;
  double flipMedian = 0.0;
  double flipMax = 0.0;
  double flipForegroundMean = 0.0;
  std::vector<float> flipMap;  // per pixel, rows top first; only with CompareOptions::keepFlipMap
  // Coverage in pixels: Σ alpha of A and of B. Holes: what B covers and A does not, Σ max(0, αB − αA);
  // bloat: what A covers and B does not, Σ max(0, αA − αB); each also as a fraction of B's coverage
  // (0 when B covers nothing). With alpha 0 or 1 these count pixels; with fractional alpha a pixel
  // half covered by B and empty in A is half a hole.
  double coverageA = 0.0;
  double coverageB = 0.0;
  double holes = 0.0;
  double bloat = 0.0;
  double holeFraction = 0.0;
  double bloatFraction = 0.0;
  std::uint64_t pixels = 0;  // width·height
};

// Compares A with B, which must be the same size (else throws std::invalid_argument). Bit-identical
// results for any thread count: every sum runs over rows in parallel and adds the rows in order.
ImageDifference compareImages(const RgbaImage& a, const RgbaImage& b, const CompareOptions& options = {});

// Pass/fail limits for image tests, in the manner of OpenImageIO's idiff: each one set is checked.
struct ImageThresholds {
  std::optional<double> maxFlip{};            // flipMean
  std::optional<double> minPsnr{};            // psnr (whole image)
  std::optional<double> minForegroundPsnr{};  // foregroundPsnr
  std::optional<double> maxHoles{};           // holeFraction
  std::optional<double> maxBloat{};           // bloatFraction
};

// One limit a comparison broke: the option's name ("--max-flip", …), the measured value and the limit.
struct ThresholdFailure {
  std::string option;
  double value = 0.0;
  double limit = 0.0;
};

// The limits `difference` breaks, in the order of ImageThresholds' fields; empty: the images pass.
// A NaN value breaks every limit on it.
std::vector<ThresholdFailure> failedThresholds(const ImageDifference& difference, const ImageThresholds& thresholds);

// The luminance SSIM of compareImages, of the colours as given (compareImages passes composited ones).
double luminanceSsim(const RgbaImage& a, const RgbaImage& b);

}  // namespace pbs
