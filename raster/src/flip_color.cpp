// FLIP's colour pipeline: YCxCz planes, contrast-sensitivity filtering, Hunt-adjusted HyAB, the colour error ΔEc.
#include "flip_color.hpp"

#include "flip_color_space.hpp"
#include "pbs/raster/simd_clones.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace pbs::flip {
namespace {

// One Gaussian of a contrast-sensitivity function in the paper's form a·√(π/b)·exp(−π²x²/b), x in
// degrees of visual angle.
struct CsfGaussian {
  double a;
  double b;
};

// The paper's constants. The achromatic and red-green functions are single Gaussians (their second
// terms have a = 0); the blue-yellow one is the sum of two.
constexpr CsfGaussian kAchromaticCsf{1.0, 0.0047};
constexpr CsfGaussian kRedGreenCsf{1.0, 0.0053};
constexpr CsfGaussian kBlueYellowBroadCsf{34.1, 0.04};
constexpr CsfGaussian kBlueYellowNarrowCsf{13.5, 0.025};
constexpr double kLargestB = 0.04;  // the widest Gaussian sets the radius of every kernel

// Colour-error mapping: HyAB^qc, then [0, pc·cmax) → [0, pt) and [pc·cmax, cmax] → [pt, 1].
constexpr float kQc = 0.7f;
constexpr float kPc = 0.4f;
constexpr float kPt = 0.95f;

// A Gaussian's taps at whole pixels, k = 0 … radius, before normalisation.
std::vector<double> sampleCsf(const CsfGaussian& g, double pixelsPerDegree, std::uint32_t radius) {
  std::vector<double> taps(radius + 1);
  for (std::uint32_t k = 0; k <= radius; ++k) {
    const double degrees = double(k) / pixelsPerDegree;
    taps[k] = std::exp(-std::numbers::pi * std::numbers::pi * degrees * degrees / g.b);
  }
  return taps;
}

double tapSum(const std::vector<double>& taps) {
  double sum = taps[0];
  for (std::size_t k = 1; k < taps.size(); ++k) sum += 2.0 * taps[k];
  return sum;
}

HalfKernel normalisedSmoothing(const std::vector<double>& taps) {
  const double sum = tapSum(taps);
  HalfKernel kernel{KernelShape::smoothing, {}};
  for (std::size_t k = 1; k < taps.size(); ++k) kernel.weights.push_back(float(taps[k] / sum));
  return kernel;
}

// cmax: the Hunt-adjusted HyAB distance between linear green and blue, raised to qc, the largest
// colour distance FLIP expects.
float largestColorDistance() {
  const glm::vec3 green = relativeXyzToHuntLab(multiply(kLinearRgbToRelativeXyz, glm::vec3(0.0f, 1.0f, 0.0f)));
  const glm::vec3 blue = relativeXyzToHuntLab(multiply(kLinearRgbToRelativeXyz, glm::vec3(0.0f, 0.0f, 1.0f)));
  return powPositive(hyab(green, blue), kQc);
}

// Filtered YCxCz back to linear RGB clamped to the display's range, then Hunt-adjusted CIELAB.
PBS_CLONE_INLINE glm::vec3 filteredToHuntLab(float achromatic, float redGreen, float blueYellow) {
  const glm::vec3 rgb =
      multiply(kRelativeXyzToLinearRgb, ycxczToRelativeXyz(glm::vec3(achromatic, redGreen, blueYellow)));
  const glm::vec3 displayable(clampToUnit(rgb.r), clampToUnit(rgb.g), clampToUnit(rgb.b));
  return relativeXyzToHuntLab(multiply(kLinearRgbToRelativeXyz, displayable));
}

// One row of sRGB display values to Y', Cx and Cz.
PBS_AVX2_CLONES
void convertRow(const glm::vec3* srgb, std::uint32_t width, float* achromatic, float* redGreen, float* blueYellow) {
  for (std::uint32_t x = 0; x < width; ++x) {
    const glm::vec3 linear(srgbToLinear(clampToUnit(srgb[x].r)), srgbToLinear(clampToUnit(srgb[x].g)),
                           srgbToLinear(clampToUnit(srgb[x].b)));
    const glm::vec3 opponent = relativeXyzToYcxcz(multiply(kLinearRgbToRelativeXyz, linear));
    achromatic[x] = opponent.x;
    redGreen[x] = opponent.y;
    blueYellow[x] = opponent.z;
  }
}

// The filtered Y', Cx and Cz of one row of one image.
struct FilteredRow {
  std::vector<float> achromatic, redGreen, blueYellow;

  explicit FilteredRow(std::uint32_t width) : achromatic(width), redGreen(width), blueYellow(width) {}
};

// ΔEc of one row from the filtered rows of the two images.
PBS_AVX2_CLONES
void colorErrorOfRow(const FilteredRow& reference, const FilteredRow& test, std::uint32_t width, float cmax,
                     float* out) {
  const float pccmax = kPc * cmax;
  const float* refY = reference.achromatic.data();
  const float* refCx = reference.redGreen.data();
  const float* refCz = reference.blueYellow.data();
  const float* testY = test.achromatic.data();
  const float* testCx = test.redGreen.data();
  const float* testCz = test.blueYellow.data();
  for (std::uint32_t x = 0; x < width; ++x) {
    const glm::vec3 refLab = filteredToHuntLab(refY[x], refCx[x], refCz[x]);
    const glm::vec3 testLab = filteredToHuntLab(testY[x], testCx[x], testCz[x]);
    const float distance = powPositive(hyab(refLab, testLab), kQc);
    const float low = (kPt / pccmax) * distance;
    const float high = kPt + (distance - pccmax) / (cmax - pccmax) * (1.0f - kPt);
    out[x] = selectFloat(distance < pccmax, low, high);
  }
}

// Buffers for filtering one row of one image.
struct RowScratch {
  std::vector<float> column;
  std::vector<float> broad;
  PaddedRow padded;

  RowScratch(std::uint32_t width, std::uint32_t radius) : column(width), broad(width), padded(width, radius) {}
};

// The filtered Y', Cx and Cz of row y.
void filterOpponentRow(const ColorFilters& filters, const OpponentPlanes& planes, std::uint32_t y, RowScratch& scratch,
                       FilteredRow& out) {
  const auto separable = [&](const Plane& plane, const HalfKernel& kernel, float* filtered) {
    filterDown(plane, y, kernel, scratch.column.data());
    scratch.padded.assign(scratch.column.data());
    filterAlong(scratch.padded, kernel, filtered);
  };
  separable(planes.achromatic, filters.achromatic, out.achromatic.data());
  separable(planes.redGreen, filters.redGreen, out.redGreen.data());
  separable(planes.blueYellow, filters.blueYellowBroad, scratch.broad.data());
  separable(planes.blueYellow, filters.blueYellowNarrow, out.blueYellow.data());
  // Blended as a difference so that where both terms agree (a flat region) the value is exact.
  float* blueYellow = out.blueYellow.data();
  const std::uint32_t width = planes.blueYellow.width;
  for (std::uint32_t x = 0; x < width; ++x) blueYellow[x] += filters.broadShare * (scratch.broad[x] - blueYellow[x]);
}

}  // namespace

OpponentPlanes toOpponentPlanes(std::span<const glm::vec3> srgb, std::uint32_t width, std::uint32_t height) {
  OpponentPlanes planes;
  for (Plane* plane : {&planes.achromatic, &planes.redGreen, &planes.blueYellow}) *plane = Plane(width, height);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, height), [&](const tbb::blocked_range<std::uint32_t>& rows) {
    for (std::uint32_t y = rows.begin(); y != rows.end(); ++y)
      convertRow(srgb.data() + std::size_t(y) * width, width, planes.achromatic.row(y), planes.redGreen.row(y),
                 planes.blueYellow.row(y));
  });
  return planes;
}

ColorFilters makeColorFilters(double pixelsPerDegree) {
  ColorFilters filters;
  const double pi = std::numbers::pi;
  filters.radius = std::uint32_t(std::ceil(3.0 * std::sqrt(kLargestB / (2.0 * pi * pi)) * pixelsPerDegree));
  filters.achromatic = normalisedSmoothing(sampleCsf(kAchromaticCsf, pixelsPerDegree, filters.radius));
  filters.redGreen = normalisedSmoothing(sampleCsf(kRedGreenCsf, pixelsPerDegree, filters.radius));
  const std::vector<double> broad = sampleCsf(kBlueYellowBroadCsf, pixelsPerDegree, filters.radius);
  const std::vector<double> narrow = sampleCsf(kBlueYellowNarrowCsf, pixelsPerDegree, filters.radius);
  filters.blueYellowBroad = normalisedSmoothing(broad);
  filters.blueYellowNarrow = normalisedSmoothing(narrow);
  // Each term's weight in the 2-D kernel: its amplitude times the sum of its separable 2-D taps.
  const auto termWeight = [&](const CsfGaussian& g, const std::vector<double>& taps) {
    const double sum = tapSum(taps);
    return g.a * std::sqrt(pi / g.b) * sum * sum;
  };
  const double broadWeight = termWeight(kBlueYellowBroadCsf, broad);
  const double narrowWeight = termWeight(kBlueYellowNarrowCsf, narrow);
  filters.broadShare = float(broadWeight / (broadWeight + narrowWeight));
  return filters;
}

void colorErrorRows(const ColorFilters& filters, const OpponentPlanes& reference, const OpponentPlanes& test,
                    std::uint32_t yBegin, std::uint32_t yEnd, float* out) {
  const std::uint32_t width = reference.achromatic.width;
  const float cmax = largestColorDistance();
  RowScratch scratch(width, filters.radius);
  FilteredRow filteredReference(width), filteredTest(width);
  for (std::uint32_t y = yBegin; y < yEnd; ++y) {
    filterOpponentRow(filters, reference, y, scratch, filteredReference);
    filterOpponentRow(filters, test, y, scratch, filteredTest);
    colorErrorOfRow(filteredReference, filteredTest, width, cmax, out + std::size_t(y - yBegin) * width);
  }
}

}  // namespace pbs::flip
