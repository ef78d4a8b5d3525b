// benchOrder: seeded sphere points, each ordering timed on one thread, then its blue-noise summary.
#include "order_bench.hpp"

#include <pbs/evaluation/report_numbers.hpp>

#include <pbs/raster/thread_arena.hpp>
#include <pbs/surfels/blue_noise_metrics.hpp>
#include <pbs/surfels/ordering.hpp>
#include <pbs/surfels/sphere_points.hpp>

#include <chrono>
#include <functional>
#include <numbers>
#include <vector>

namespace pbs::bench {

namespace {

using Ordering = std::function<std::vector<std::uint32_t>()>;

nlohmann::json measure(const std::vector<glm::vec3>& points, const Ordering& ordering) {
  std::vector<std::uint32_t> order;
  const auto start = std::chrono::steady_clock::now();
  runWithThreads(1, [&] { order = ordering(); });
  const double seconds = secondsSince(start);
  const BlueNoiseSummary summary = summarizeBlueNoise(points, order, 4.0 * std::numbers::pi);
  return {{"seconds", seconds}, {"count", order.size()}, {"rho_min", summary.rhoMin}, {"rho_mean", summary.rhoMean}};
}

}  // namespace

nlohmann::json benchOrder(std::uint64_t points, std::uint32_t max, std::uint64_t seed) {
  const std::vector<glm::vec3> sphere = uniformSpherePoints(points, seed);
  nlohmann::json report;
  report["points"] = points;
  report["max"] = max;
  report["farthest"] = measure(sphere, [&] { return orderFarthest(sphere, max, seed); });
  report["dart"] = measure(sphere, [&] { return orderDart(sphere, max, seed, 200); });
  report["random"] = measure(sphere, [&] { return orderRandom(sphere, max, seed); });
  report["ratios"] = {{"dart_over_farthest_seconds",
                       report["dart"]["seconds"].get<double>() / report["farthest"]["seconds"].get<double>()}};
  return report;
}

}  // namespace pbs::bench
