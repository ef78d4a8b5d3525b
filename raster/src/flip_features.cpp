// FLIP's feature pipeline: edges and points of the luminance, and their difference ΔEf.
#include "flip_features.hpp"

#include "flip_branchless.hpp"
#include "pbs/raster/simd_clones.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace pbs::flip {
namespace {

constexpr double kFeatureWidthDegrees = 0.082;  // the paper's w: σ = w/2 degrees

// Scales a derivative kernel so that its positive taps sum to 1 and its negative ones to −1. `centre`
// is its tap at 0 (implied by the shape, not stored); `taps` are those at +1 … +radius, and each
// stands for two, its mirror at −k being equal (even kernel) or opposite (odd). A kernel with no
// tap of one sign (at a resolution too coarse for it) is all zeros: the detector sees nothing rather
// than a biased response.
HalfKernel balancedDerivative(KernelShape shape, double centre, const std::vector<double>& taps) {
  double positive = std::max(centre, 0.0), negative = std::max(-centre, 0.0);
  for (double t : taps) {
    const double mirrored = shape == KernelShape::slope ? -t : t;
    for (double v : {t, mirrored}) {
      if (v > 0.0)
        positive += v;
      else
        negative -= v;
    }
  }
  HalfKernel kernel{shape, std::vector<float>(taps.size(), 0.0f)};
  if (positive == 0.0 || negative == 0.0) return kernel;
  for (std::size_t k = 0; k < taps.size(); ++k)
    kernel.weights[k] = float(taps[k] / (taps[k] > 0.0 ? positive : negative));
  return kernel;
}

// Buffers for the detector responses of one row of one image.
struct RowScratch {
  std::vector<float> smoothed, slope, curvature;  // down the columns: Gaussian, edge, point
  std::vector<float> dx, dy, ddx, ddy;
  PaddedRow padded;

  RowScratch(std::uint32_t width, std::uint32_t radius)
      : smoothed(width),
        slope(width),
        curvature(width),
        dx(width),
        dy(width),
        ddx(width),
        ddy(width),
        padded(width, radius) {}
};

// Lengths of the (x, y) responses, scaled from Y' to luminance.
PBS_AVX2_CLONES
void magnitudes(const RowScratch& s, std::uint32_t width, float* edges, float* points) {
  constexpr float toLuminance = 1.0f / 116.0f;
  for (std::uint32_t x = 0; x < width; ++x) {
    edges[x] = sqrtNonNegative(s.dx[x] * s.dx[x] + s.dy[x] * s.dy[x]) * toLuminance;
    points[x] = sqrtNonNegative(s.ddx[x] * s.ddx[x] + s.ddy[x] * s.ddy[x]) * toLuminance;
  }
}

// ΔEf = (max(|Δedge|, |Δpoint|) / √2)^qf, qf = 1/2.
PBS_AVX2_CLONES
void featureErrorOfRow(const float* refEdges, const float* refPoints, const float* testEdges, const float* testPoints,
                       std::uint32_t width, float* out) {
  const float invSqrt2 = float(1.0 / std::numbers::sqrt2);
  for (std::uint32_t x = 0; x < width; ++x) {
    const float difference = std::max(std::abs(refEdges[x] - testEdges[x]), std::abs(refPoints[x] - testPoints[x]));
    out[x] = sqrtNonNegative(difference * invSqrt2);
  }
}

// Edge and point magnitudes of row y, for luminance Y/Yn = (Y' + 16)/116. Each 2-D detector (a
// derivative along one axis times a Gaussian along the other) sums to zero, so the offset adds
// nothing and the scale factors out: they run on Y' itself and the magnitudes are divided by 116.
void featureMagnitudes(const FeatureFilters& filters, const Plane& achromatic, std::uint32_t y, RowScratch& s,
                       float* edges, float* points) {
  filterDown(achromatic, y, filters.gaussian, s.smoothed.data());
  filterDown(achromatic, y, filters.edge, s.slope.data());
  filterDown(achromatic, y, filters.point, s.curvature.data());
  s.padded.assign(s.smoothed.data());
  filterAlong(s.padded, filters.edge, s.dx.data());
  filterAlong(s.padded, filters.point, s.ddx.data());
  s.padded.assign(s.slope.data());
  filterAlong(s.padded, filters.gaussian, s.dy.data());
  s.padded.assign(s.curvature.data());
  filterAlong(s.padded, filters.gaussian, s.ddy.data());
  magnitudes(s, achromatic.width, edges, points);
}

}  // namespace

FeatureFilters makeFeatureFilters(double pixelsPerDegree) {
  const double sigma = 0.5 * kFeatureWidthDegrees * pixelsPerDegree;  // in pixels
  const std::uint32_t radius = std::uint32_t(std::ceil(3.0 * sigma));
  std::vector<double> gaussian(radius), edge(radius), point(radius);
  double gaussianSum = 1.0;  // the centre tap, exp(0)
  for (std::uint32_t k = 1; k <= radius; ++k) {
    const double x = double(k);
    const double g = std::exp(-x * x / (2.0 * sigma * sigma));
    gaussian[k - 1] = g;
    gaussianSum += 2.0 * g;
    edge[k - 1] = -x * g;                                // d/dx of the Gaussian, up to scale
    point[k - 1] = (x * x / (sigma * sigma) - 1.0) * g;  // d²/dx², up to scale
  }
  FeatureFilters filters;
  filters.gaussian = HalfKernel{KernelShape::smoothing, {}};
  for (double g : gaussian) filters.gaussian.weights.push_back(float(g / gaussianSum));
  filters.edge = balancedDerivative(KernelShape::slope, 0.0, edge);
  filters.point = balancedDerivative(KernelShape::curvature, -1.0, point);  // (0 − 1)·exp(0) at the centre
  return filters;
}

void featureErrorRows(const FeatureFilters& filters, const Plane& reference, const Plane& test, std::uint32_t yBegin,
                      std::uint32_t yEnd, float* out) {
  const std::uint32_t width = reference.width;
  RowScratch scratch(width, filters.gaussian.radius());
  std::vector<float> refEdges(width), refPoints(width), testEdges(width), testPoints(width);
  for (std::uint32_t y = yBegin; y < yEnd; ++y) {
    featureMagnitudes(filters, reference, y, scratch, refEdges.data(), refPoints.data());
    featureMagnitudes(filters, test, y, scratch, testEdges.data(), testPoints.data());
    featureErrorOfRow(refEdges.data(), refPoints.data(), testEdges.data(), testPoints.data(), width,
                      out + std::size_t(y - yBegin) * width);
  }
}

}  // namespace pbs::flip
