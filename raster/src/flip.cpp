// LDR-FLIP of two sRGB pictures: checks the input, runs the colour and feature pipelines by rows, pools the map.
#include <pbs/raster/flip.hpp>

#include "flip_branchless.hpp"
#include "flip_color.hpp"
#include "flip_features.hpp"
#include "flip_median.hpp"
#include "pbs/raster/simd_clones.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace pbs {
namespace {

void requireValidInput(std::size_t referenceSize, std::size_t testSize, std::uint32_t width, std::uint32_t height,
                       double pixelsPerDegree) {
  const std::size_t pixels = std::size_t(width) * height;
  if (referenceSize != pixels || testSize != pixels)
    throw std::invalid_argument("FLIP: images of " + std::to_string(referenceSize) + " and " +
                                std::to_string(testSize) + " pixels, expected " + std::to_string(width) + "x" +
                                std::to_string(height));
  if (!(pixelsPerDegree > 0.0 && pixelsPerDegree <= kMaxPixelsPerDegree))
    throw std::invalid_argument("FLIP: pixels per degree must be in (0, " + std::to_string(kMaxPixelsPerDegree) +
                                "], got " + std::to_string(pixelsPerDegree));
}

// FLIP = ΔEc^(1 − ΔEf), in place of ΔEc.
PBS_AVX2_CLONES
void combineErrors(float* colorError, const float* featureError, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) colorError[i] = flip::powPositive(colorError[i], 1.0f - featureError[i]);
}

}  // namespace

FlipResult computeFlip(std::span<const glm::vec3> reference, std::span<const glm::vec3> test, std::uint32_t width,
                       std::uint32_t height, double pixelsPerDegree, bool keepMap) {
  requireValidInput(reference.size(), test.size(), width, height, pixelsPerDegree);
  FlipResult result;
  if (reference.empty()) return result;

  const flip::OpponentPlanes referencePlanes = flip::toOpponentPlanes(reference, width, height);
  const flip::OpponentPlanes testPlanes = flip::toOpponentPlanes(test, width, height);
  const flip::ColorFilters colorFilters = flip::makeColorFilters(pixelsPerDegree);
  const flip::FeatureFilters featureFilters = flip::makeFeatureFilters(pixelsPerDegree);

  std::vector<float> map(reference.size());
  // Summed per row, then the rows in order: the mean cannot depend on how rows were shared out.
  std::vector<double> rowSums(height);
  std::vector<float> rowMaxima(height);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, height), [&](const tbb::blocked_range<std::uint32_t>& rows) {
    float* colorError = map.data() + std::size_t(rows.begin()) * width;
    flip::colorErrorRows(colorFilters, referencePlanes, testPlanes, rows.begin(), rows.end(), colorError);
    std::vector<float> featureError(std::size_t(rows.size()) * width);
    flip::featureErrorRows(featureFilters, referencePlanes.achromatic, testPlanes.achromatic, rows.begin(), rows.end(),
                           featureError.data());
    combineErrors(colorError, featureError.data(), featureError.size());
    for (std::uint32_t y = rows.begin(); y != rows.end(); ++y) {
      const float* row = colorError + std::size_t(y - rows.begin()) * width;
      double sum = 0.0;
      for (std::uint32_t x = 0; x < width; ++x) sum += row[x];
      rowSums[y] = sum;
      rowMaxima[y] = *std::max_element(row, row + width);
    }
  });

  double total = 0.0;
  for (double s : rowSums) total += s;
  result.mean = total / double(map.size());
  result.max = *std::max_element(rowMaxima.begin(), rowMaxima.end());
  result.median = flip::medianOfNonNegative(map);
  if (keepMap) result.map = std::move(map);
  return result;
}

}  // namespace pbs
