// Blue-noise measures of ordered prefixes: minimum distances from incremental nearest-neighbour queries, mean
// nearest-neighbour distances from every point's nearest neighbour found at once.
#include "all_nearest_neighbours.hpp"
#include "order_nearest_grid.hpp"

#include <pbs/surfels/blue_noise_metrics.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace pbs {

namespace {

// An order from a file or a caller may hold anything: an index past the points is an error, not a read.
void checkIndices(std::span<const glm::vec3> points, std::span<const std::uint32_t> order, const char* who) {
  for (std::size_t k = 0; k < order.size(); ++k) {
    if (order[k] >= points.size()) {
      std::string message(who);
      message.append(": order entry ").append(std::to_string(k)).append(" is ").append(std::to_string(order[k]));
      message.append(", past the ").append(std::to_string(points.size())).append(" points");
      throw std::invalid_argument(message);
    }
  }
}

}  // namespace

std::vector<double> prefixMinDistances(std::span<const glm::vec3> points, std::span<const std::uint32_t> order) {
  checkIndices(points, order, "prefixMinDistances");
  std::vector<double> minDistance(order.size(), std::numeric_limits<double>::infinity());
  NearestPointGrid prefix(points, order, "prefixMinDistances");
  double running = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < order.size(); ++k) {
    const float d2 = prefix.nearestSquared(points[order[k]]);
    running = std::min(running, std::sqrt(static_cast<double>(d2)));
    minDistance[k] = running;
    prefix.insert(order[k]);
  }
  return minDistance;
}

double relativeRadius(double minDistance, std::size_t k, double area) {
  if (!(area > 0.0) || k == 0) return 0.0;  // negated so a NaN area gives 0 too
  return minDistance / std::sqrt(2.0 * area / (std::sqrt(3.0) * static_cast<double>(k)));
}

double meanNearestNeighbourDistance(std::span<const glm::vec3> points, std::span<const std::uint32_t> order,
                                    std::size_t count) {
  count = std::min(count, order.size());
  if (count < 2) return 0.0;
  checkIndices(points, order.first(count), "meanNearestNeighbourDistance");
  std::vector<glm::vec3> prefix(count);
  for (std::size_t k = 0; k < count; ++k) prefix[k] = points[order[k]];
  const std::vector<float> nearest = allNearestSquared(prefix, "meanNearestNeighbourDistance", order.first(count));
  double sum = 0.0;
  for (float squared : nearest) sum += std::sqrt(static_cast<double>(squared));
  return sum / static_cast<double>(count);
}

BlueNoiseSummary summarizeBlueNoise(std::span<const glm::vec3> points, std::span<const std::uint32_t> order,
                                    double area) {
  BlueNoiseSummary summary;
  const std::size_t n = order.size();
  if (n < 2) return summary;
  const std::vector<double> minDistance = prefixMinDistances(points, order);
  const auto rho = [&](std::size_t k) { return relativeRadius(minDistance[k - 1], k, area); };
  // Below ~100 points ρ measures the luck of the first few picks rather than the ordering.
  const std::size_t firstK = std::min<std::size_t>(100, n);
  const std::size_t startK = std::max<std::size_t>(2, firstK);
  summary.rhoMin = std::numeric_limits<double>::infinity();
  for (std::size_t k = startK; k <= n; ++k) summary.rhoMin = std::min(summary.rhoMin, rho(k));
  constexpr int kSamples = 32;
  const double logSpan = std::log(static_cast<double>(n) / static_cast<double>(startK));
  double sum = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    const double k = static_cast<double>(startK) * std::exp(logSpan * i / (kSamples - 1));
    sum += rho(std::clamp<std::size_t>(static_cast<std::size_t>(std::llround(k)), startK, n));
  }
  summary.rhoMean = sum / kSamples;
  return summary;
}

}  // namespace pbs
