// Periodograms of 2-D point sets by direct DFT over separable exponential tables, and their radial means.
#include <pbs/raster/seeded_random.hpp>
#include <pbs/surfels/point_spectrum.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace pbs {

std::vector<double> periodogram(std::span<const glm::vec2> points, std::uint32_t maxFrequency) {
  const std::size_t n = points.size();
  const std::size_t width = 2 * std::size_t(maxFrequency) + 1;
  const int f0 = -int(maxFrequency);
  std::vector<double> power(width * width, 0.0);
  if (n == 0) return power;
  // Per point, exp(-2πi f x) for every f on each axis (point-major, so a row's accumulation over the
  // points is a vectorizable update of independent per-frequency sums).
  std::vector<double> xRe(n * width), xIm(n * width), yRe(n * width), yIm(n * width);
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t j) {
    for (std::size_t i = 0; i < width; ++i) {
      const double f = double(f0 + int(i));
      const double ax = -2.0 * std::numbers::pi * f * double(points[j].x);
      const double ay = -2.0 * std::numbers::pi * f * double(points[j].y);
      xRe[j * width + i] = std::cos(ax);
      xIm[j * width + i] = std::sin(ax);
      yRe[j * width + i] = std::cos(ay);
      yIm[j * width + i] = std::sin(ay);
    }
  });
  // Real points: P(-f) = P(f), so only rows fy ≥ 0 are summed and the others mirrored.
  tbb::parallel_for(std::size_t(maxFrequency), width, [&](std::size_t row) {
    std::vector<double> sumRe(width, 0.0), sumIm(width, 0.0);
    double* __restrict re = sumRe.data();
    double* __restrict im = sumIm.data();
    for (std::size_t j = 0; j < n; ++j) {
      const double wRe = yRe[j * width + row], wIm = yIm[j * width + row];
      const double* __restrict aRe = xRe.data() + j * width;
      const double* __restrict aIm = xIm.data() + j * width;
      for (std::size_t i = 0; i < width; ++i) {
        re[i] += aRe[i] * wRe - aIm[i] * wIm;
        im[i] += aRe[i] * wIm + aIm[i] * wRe;
      }
    }
    for (std::size_t i = 0; i < width; ++i) {
      const double p = (re[i] * re[i] + im[i] * im[i]) / double(n);
      power[row * width + i] = p;
      power[(width - 1 - row) * width + (width - 1 - i)] = p;
    }
  });
  return power;
}

RadialSpectrum radialSpectrum(std::span<const double> periodogram, std::uint32_t maxFrequency) {
  const std::size_t width = 2 * std::size_t(maxFrequency) + 1;
  if (periodogram.size() != width * width)
    throw std::invalid_argument("radialSpectrum: periodogram size does not match the frequency range");
  std::vector<double> sum(maxFrequency + 1, 0.0), sumSquares(maxFrequency + 1, 0.0);
  std::vector<std::size_t> samples(maxFrequency + 1, 0);
  const int f0 = -int(maxFrequency);
  for (std::size_t row = 0; row < width; ++row) {
    for (std::size_t i = 0; i < width; ++i) {
      const double fx = double(f0 + int(i)), fy = double(f0 + int(row));
      const auto r = std::size_t(std::llround(std::sqrt(fx * fx + fy * fy)));
      if (r == 0 || r > maxFrequency) continue;
      const double p = periodogram[row * width + i];
      sum[r] += p;
      sumSquares[r] += p * p;
      ++samples[r];
    }
  }
  RadialSpectrum radial;
  for (std::size_t r = 1; r <= maxFrequency; ++r) {
    const double count = double(samples[r]);
    const double mean = sum[r] / count;
    const double variance = std::max(0.0, sumSquares[r] / count - mean * mean);
    radial.frequency.push_back(double(r));
    radial.power.push_back(mean);
    // A floor keeps a perfectly isotropic annulus (variance 0) finite: -100 dB.
    radial.anisotropy.push_back(mean > 0.0 ? 10.0 * std::log10(std::max(variance / (mean * mean), 1e-10)) : 0.0);
  }
  return radial;
}

FlatSpectrum flatPatchSpectrum(const PointOrdering& ordering, const FlatSpectrumOptions& options) {
  if (options.candidates == 0 || options.count == 0 || options.realizations == 0)
    throw std::invalid_argument("flatPatchSpectrum: candidates, count and realizations must be positive");
  if (options.count > options.candidates)
    throw std::invalid_argument("flatPatchSpectrum: count exceeds the candidates");
  if (options.count > std::numeric_limits<std::uint32_t>::max() / 4 ||
      options.candidates > std::numeric_limits<std::uint32_t>::max() / 4)
    throw std::invalid_argument("flatPatchSpectrum: count or candidates too large");
  FlatSpectrum result;
  result.maxFrequency =
      options.maxFrequency != 0
          ? options.maxFrequency
          : std::max<std::uint32_t>(1, std::uint32_t(std::lround(4.0 * std::sqrt(double(options.count)))));
  const std::size_t width = 2 * std::size_t(result.maxFrequency) + 1;
  std::vector<double> mean(width * width, 0.0);
  // The ordered patch is [0, 2)² with 4× the candidates and 4× the points; the measured window is its
  // central [0.5, 1.5)², where the ordering is away from the patch's edges (farthest-point order
  // favours edges, which a window over the whole patch would show as excess power at low frequencies).
  // At integer frequencies the window's own transform is zero, so cutting it out adds no bias.
  std::vector<glm::vec3> candidates(std::size_t(options.candidates) * 4);
  std::uint64_t measured = 0;
  for (std::uint32_t s = 0; s < options.realizations; ++s) {
    const std::uint64_t seed = options.seed + s;
    // The candidates' stream is derived from the seed so that it differs from the ordering's own.
    SeededRandom random(SeededRandom(seed).next() ^ 0x6A09E667F3BCC909ull);
    for (glm::vec3& c : candidates) c = glm::vec3(float(2.0 * random.unit()), float(2.0 * random.unit()), 0.0f);
    const std::vector<std::uint32_t> order = ordering(candidates, options.count * 4, seed);
    std::vector<glm::vec2> chosen;
    chosen.reserve(order.size());
    for (std::uint32_t index : order) {
      const glm::vec2 p = glm::vec2(candidates[index]) - 0.5f;
      if (p.x >= 0.0f && p.x < 1.0f && p.y >= 0.0f && p.y < 1.0f) chosen.push_back(p);
    }
    measured += chosen.size();
    const std::vector<double> p = periodogram(chosen, result.maxFrequency);
    for (std::size_t i = 0; i < p.size(); ++i) mean[i] += p[i] / double(options.realizations);
  }
  result.count = std::uint32_t((measured + options.realizations / 2) / options.realizations);
  result.radial = radialSpectrum(mean, result.maxFrequency);
  const auto lowEnd =
      std::clamp<std::size_t>(std::size_t(std::sqrt(double(result.count)) / 2.0), 1, result.radial.power.size());
  double low = 0.0;
  for (std::size_t r = 0; r < lowEnd; ++r) low += result.radial.power[r];
  result.lowFrequencyPower = low / double(lowEnd);
  return result;
}

}  // namespace pbs
