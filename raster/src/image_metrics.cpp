// Image-difference metrics over float RGBA pictures: composited PSNR (whole and foreground), luminance
// SSIM, FLIP, coverage holes and bloat, and the pass/fail check of image tests.
#include <pbs/raster/image_metrics.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pbs {
namespace {

constexpr std::uint32_t kSsimWindow = 11;
constexpr double kSsimSigma = 1.5;
constexpr double kSsimC1 = 0.01 * 0.01;  // (K1·L)², L = 1
constexpr double kSsimC2 = 0.03 * 0.03;  // (K2·L)²

void requireSameSize(const RgbaImage& a, const RgbaImage& b) {
  if (a.pixels.size() != a.pixelCount() || b.pixels.size() != b.pixelCount())
    throw std::invalid_argument("image pixel count does not match its width × height");
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument("images differ in size: " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                                " and " + std::to_string(b.width) + "x" + std::to_string(b.height));
}

// Y of every pixel (RGBA or RGB: alpha plays no part).
template <typename Pixel>
std::vector<double> luminance(const std::vector<Pixel>& pixels) {
  std::vector<double> y(pixels.size());
  for (std::size_t i = 0; i < y.size(); ++i) {
    const Pixel& p = pixels[i];
    y[i] = 0.2126 * double(p.r) + 0.7152 * double(p.g) + 0.0722 * double(p.b);
  }
  return y;
}

// Normalised Gaussian weights over `size` taps centred on the middle one (the standard 11, or a
// shorter side's whole length).
std::vector<double> gaussianWeights(std::uint32_t size) {
  std::vector<double> weights(size);
  const double centre = 0.5 * double(size - 1);
  double sum = 0.0;
  for (std::uint32_t i = 0; i < size; ++i) {
    const double d = double(i) - centre;
    weights[i] = std::exp(-d * d / (2.0 * kSsimSigma * kSsimSigma));
    sum += weights[i];
  }
  for (double& w : weights) w /= sum;
  return weights;
}

// Mean SSIM of two width × height luminance images (at least one pixel).
double ssimOfLuminance(const std::vector<double>& ya, const std::vector<double>& yb, std::uint32_t width,
                       std::uint32_t height) {
  const std::uint32_t windowX = std::min(kSsimWindow, width);
  const std::uint32_t windowY = std::min(kSsimWindow, height);
  const std::vector<double> weightsX = gaussianWeights(windowX);
  const std::vector<double> weightsY = gaussianWeights(windowY);
  const std::uint32_t outWidth = width - windowX + 1;
  const std::uint32_t outHeight = height - windowY + 1;

  // One sum per window row, each summed left to right by one task: the total cannot depend on how
  // the rows were shared out.
  std::vector<double> rowSums(outHeight);
  const tbb::blocked_range<std::uint32_t> allRows(0, outHeight, 4);
  tbb::parallel_for(allRows, [&](const tbb::blocked_range<std::uint32_t>& rows) {
    // Vertical weighted sums of a, b, a², b², ab for every column of the current window row.
    std::vector<double> ma(width), mb(width), maa(width), mbb(width), mab(width);
    for (std::uint32_t top = rows.begin(); top != rows.end(); ++top) {
      std::fill(ma.begin(), ma.end(), 0.0);
      std::fill(mb.begin(), mb.end(), 0.0);
      std::fill(maa.begin(), maa.end(), 0.0);
      std::fill(mbb.begin(), mbb.end(), 0.0);
      std::fill(mab.begin(), mab.end(), 0.0);
      for (std::uint32_t k = 0; k < windowY; ++k) {
        const double w = weightsY[k];
        const double* rowA = ya.data() + std::size_t(top + k) * width;
        const double* rowB = yb.data() + std::size_t(top + k) * width;
        for (std::uint32_t x = 0; x < width; ++x) {
          const double va = rowA[x], vb = rowB[x];
          ma[x] += w * va;
          mb[x] += w * vb;
          maa[x] += w * va * va;
          mbb[x] += w * vb * vb;
          mab[x] += w * va * vb;
        }
      }
      double sum = 0.0;
      for (std::uint32_t left = 0; left < outWidth; ++left) {
        double muA = 0.0, muB = 0.0, eAA = 0.0, eBB = 0.0, eAB = 0.0;
        for (std::uint32_t k = 0; k < windowX; ++k) {
          const double w = weightsX[k];
          const std::uint32_t x = left + k;
          muA += w * ma[x];
          muB += w * mb[x];
          eAA += w * maa[x];
          eBB += w * mbb[x];
          eAB += w * mab[x];
        }
        const double varA = eAA - muA * muA;
        const double varB = eBB - muB * muB;
        const double covariance = eAB - muA * muB;
        sum += ((2.0 * muA * muB + kSsimC1) * (2.0 * covariance + kSsimC2)) /
               ((muA * muA + muB * muB + kSsimC1) * (varA + varB + kSsimC2));
      }
      rowSums[top] = sum;
    }
  });
  double total = 0.0;
  for (double s : rowSums) total += s;
  return total / (double(outWidth) * double(outHeight));
}

// Sums of one row of the comparison; rows are added in order afterwards, so the totals do not depend
// on how the rows were shared out.
struct RowSums {
  double squares = 0.0;            // over all pixels, R + G + B
  double foregroundSquares = 0.0;  // over foreground pixels
  std::uint64_t foregroundPixels = 0;
  double coverageA = 0.0, coverageB = 0.0, holes = 0.0, bloat = 0.0;
  double foregroundFlip = 0.0;
};

float coverage(float alpha) { return alpha > 0.0f ? std::min(alpha, 1.0f) : 0.0f; }  // NaN counts as 0

// Straight colour over the background; a NaN or infinite colour component counts as 0, so one bad
// pixel of a float image costs its own error and cannot turn every sum into NaN.
glm::vec3 composite(const glm::vec4& pixel, const glm::vec3& background) {
  const float alpha = coverage(pixel.a);
  glm::vec3 colour(pixel);
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(colour[c])) colour[c] = 0.0f;
  return colour * alpha + background * (1.0f - alpha);
}

double psnrOf(double squares, double values) {
  if (!(values > 0.0)) return std::numeric_limits<double>::infinity();
  const double mse = squares / values;
  return mse > 0.0 ? -10.0 * std::log10(mse) : std::numeric_limits<double>::infinity();
}

// Every pixel composited: what FLIP, SSIM and the squared differences all read.
std::vector<glm::vec3> compositeImage(const RgbaImage& image, const glm::vec3& background) {
  std::vector<glm::vec3> out(image.pixels.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, image.pixels.size(), 4096),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i)
                        out[i] = composite(image.pixels[i], background);
                    });
  return out;
}

}  // namespace

double luminanceSsim(const RgbaImage& a, const RgbaImage& b) {
  requireSameSize(a, b);
  if (a.pixelCount() == 0) return 1.0;
  return ssimOfLuminance(luminance(a.pixels), luminance(b.pixels), a.width, a.height);
}

ImageDifference compareImages(const RgbaImage& a, const RgbaImage& b, const CompareOptions& options) {
  requireSameSize(a, b);
  ImageDifference d;
  d.pixels = a.pixelCount();
  if (d.pixels == 0) return d;
  const std::vector<glm::vec3> compositeA = compositeImage(a, options.background);
  const std::vector<glm::vec3> compositeB = compositeImage(b, options.background);
  if (options.flip) {
    // FLIP clamps its input to [0, 1] itself.
    FlipResult flip = computeFlip(compositeB, compositeA, a.width, a.height, options.pixelsPerDegree, true);
    d.flipMean = flip.mean;
    d.flipMedian = flip.median;
    d.flipMax = flip.max;
    d.flipMap = std::move(flip.map);
  }

  const std::uint32_t width = a.width;
  std::vector<RowSums> rows(a.height);
  tbb::parallel_for(std::uint32_t(0), a.height, [&](std::uint32_t y) {
    RowSums& row = rows[y];
    for (std::size_t i = std::size_t(y) * width, end = i + width; i < end; ++i) {
      const float alphaA = coverage(a.pixels[i].a), alphaB = coverage(b.pixels[i].a);
      const glm::vec3 difference = compositeA[i] - compositeB[i];
      double squares = 0.0;
      for (int c = 0; c < 3; ++c) squares += double(difference[c]) * double(difference[c]);
      row.squares += squares;
      row.coverageA += alphaA;
      row.coverageB += alphaB;
      row.holes += std::max(0.0f, alphaB - alphaA);
      row.bloat += std::max(0.0f, alphaA - alphaB);
      if (alphaA > 0.0f || alphaB > 0.0f) {
        row.foregroundSquares += squares;
        ++row.foregroundPixels;
        if (!d.flipMap.empty()) row.foregroundFlip += d.flipMap[i];
      }
    }
  });
  RowSums total;
  for (const RowSums& row : rows) {
    total.squares += row.squares;
    total.foregroundSquares += row.foregroundSquares;
    total.foregroundPixels += row.foregroundPixels;
    total.coverageA += row.coverageA;
    total.coverageB += row.coverageB;
    total.holes += row.holes;
    total.bloat += row.bloat;
    total.foregroundFlip += row.foregroundFlip;
  }
  d.rmse = std::sqrt(total.squares / (3.0 * double(d.pixels)));
  d.psnr = psnrOf(total.squares, 3.0 * double(d.pixels));
  d.foregroundPixels = total.foregroundPixels;
  d.foregroundRmse =
      total.foregroundPixels > 0 ? std::sqrt(total.foregroundSquares / (3.0 * double(total.foregroundPixels))) : 0.0;
  d.foregroundPsnr = psnrOf(total.foregroundSquares, 3.0 * double(total.foregroundPixels));
  d.flipForegroundMean = total.foregroundPixels > 0 ? total.foregroundFlip / double(total.foregroundPixels) : 0.0;
  d.coverageA = total.coverageA;
  d.coverageB = total.coverageB;
  d.holes = total.holes;
  d.bloat = total.bloat;
  d.holeFraction = total.coverageB > 0.0 ? total.holes / total.coverageB : 0.0;
  d.bloatFraction = total.coverageB > 0.0 ? total.bloat / total.coverageB : 0.0;
  d.ssim = ssimOfLuminance(luminance(compositeA), luminance(compositeB), a.width, a.height);
  if (!options.keepFlipMap) d.flipMap = {};
  return d;
}

std::vector<ThresholdFailure> failedThresholds(const ImageDifference& d, const ImageThresholds& t) {
  std::vector<ThresholdFailure> failures;
  // `above` limits fail when the value is larger, the others when it is smaller; NaN fails both.
  const auto check = [&](const char* option, const std::optional<double>& limit, double value, bool maximum) {
    if (!limit) return;
    const bool passes = maximum ? value <= *limit : value >= *limit;
    if (!passes) failures.push_back({option, value, *limit});
  };
  check("--max-flip", t.maxFlip, d.flipMean, true);
  check("--min-psnr", t.minPsnr, d.psnr, false);
  check("--min-foreground-psnr", t.minForegroundPsnr, d.foregroundPsnr, false);
  check("--max-holes", t.maxHoles, d.holeFraction, true);
  check("--max-bloat", t.maxBloat, d.bloatFraction, true);
  return failures;
}

}  // namespace pbs
