// The rotated-grid sample pattern, the shifted cameras that sample it, and the box-filter resolve.
#include "pbs/raster/supersampling.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pbs {
namespace {

std::uint32_t sideOf(std::uint32_t samples) {
  const auto side = std::uint32_t(std::lround(std::sqrt(double(samples))));
  return side * side == samples ? side : 0;
}

}  // namespace

bool isSupportedSampleCount(std::uint32_t samples) { return samples >= 1 && samples <= 256 && sideOf(samples) != 0; }

std::vector<glm::dvec2> subpixelSamples(std::uint32_t samples) {
  if (!isSupportedSampleCount(samples))
    throw std::invalid_argument("subpixelSamples: " + std::to_string(samples) +
                                " samples per pixel; supported: 1, 4, 16, 64, 256");
  const std::uint32_t side = sideOf(samples);
  const double n = double(samples);
  std::vector<glm::dvec2> positions;
  positions.reserve(samples);
  for (std::uint32_t i = 0; i < side; ++i)
    for (std::uint32_t j = 0; j < side; ++j)
      positions.emplace_back((double(i * side + j) + 0.5) / n, (double(j * side + (side - 1 - i)) + 0.5) / n);
  return positions;
}

Camera subpixelCamera(const Camera& camera, const glm::dvec2& sample, std::uint32_t samples) {
  // Window x grows with NDC x and window y shrinks with NDC y (camera.hpp): to move the sampled
  // point by +d pixels, the image moves by −d, i.e. NDC by (−2·dx / W, +2·dy / H), times w in clip space.
  const glm::dvec2 shift = sample - glm::dvec2(0.5);
  glm::dmat4 translate(1.0);
  translate[3][0] = -2.0 * shift.x / double(camera.width);
  translate[3][1] = 2.0 * shift.y / double(camera.height);
  Camera shifted = camera;
  shifted.projection = translate * camera.projection;
  shifted.sampleSpacing = camera.sampleSpacing / std::sqrt(double(std::max<std::uint32_t>(samples, 1)));
  return shifted;
}

std::vector<glm::vec4> resolveSamples(const SampleSums& sums) {
  if (sums.samples == 0) throw std::invalid_argument("resolveSamples: no samples");
  std::vector<glm::vec4> image(sums.sums.size());
  const float perSample = 1.0f / float(sums.samples);
  // Each pixel on its own: any split of the range gives the same bits.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, image.size(), 4096),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        const glm::vec4& sum = sums.sums[i];
                        if (sum.a > 0.0f) image[i] = glm::vec4(glm::vec3(sum) / sum.a, sum.a * perSample);
                      }
                    });
  return image;
}

}  // namespace pbs
