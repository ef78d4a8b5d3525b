// Image-difference metrics over float RGBA pictures: RMSE, PSNR, luminance SSIM and hole fraction.
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

std::vector<double> luminance(const RgbaImage& image) {
  std::vector<double> y(image.pixels.size());
  for (std::size_t i = 0; i < y.size(); ++i) {
    const glm::vec4& p = image.pixels[i];
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

}  // namespace

double luminanceSsim(const RgbaImage& a, const RgbaImage& b) {
  requireSameSize(a, b);
  if (a.pixelCount() == 0) return 1.0;
  const std::uint32_t width = a.width;
  const std::vector<double> ya = luminance(a);
  const std::vector<double> yb = luminance(b);
  const std::uint32_t windowX = std::min(kSsimWindow, a.width);
  const std::uint32_t windowY = std::min(kSsimWindow, a.height);
  const std::vector<double> weightsX = gaussianWeights(windowX);
  const std::vector<double> weightsY = gaussianWeights(windowY);
  const std::uint32_t outWidth = a.width - windowX + 1;
  const std::uint32_t outHeight = a.height - windowY + 1;

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

ImageDifference compareImages(const RgbaImage& a, const RgbaImage& b) {
  requireSameSize(a, b);
  ImageDifference d;
  d.pixels = a.pixelCount();
  double squares = 0.0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    const glm::vec4& pa = a.pixels[i];
    const glm::vec4& pb = b.pixels[i];
    for (int c = 0; c < 3; ++c) {
      const double diff = double(pa[c]) - double(pb[c]);
      squares += diff * diff;
    }
    const bool surfaceA = pa.a >= kSurfaceAlpha;
    const bool surfaceB = pb.a >= kSurfaceAlpha;
    d.surfaceA += surfaceA;
    d.surfaceB += surfaceB;
    d.holes += !surfaceA && surfaceB;
  }
  if (d.pixels > 0) {
    const double mse = squares / (3.0 * double(d.pixels));
    d.rmse = std::sqrt(mse);
    d.psnr = mse > 0.0 ? -10.0 * std::log10(mse) : std::numeric_limits<double>::infinity();
  }
  d.ssim = luminanceSsim(a, b);
  d.holeFraction = d.surfaceB > 0 ? double(d.holes) / double(d.surfaceB) : 0.0;
  return d;
}

}  // namespace pbs
