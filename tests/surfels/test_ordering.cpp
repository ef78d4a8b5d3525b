// Progressive orderings and blue-noise metrics: exactness against brute force, ρ ranges, stiff inputs.
#include <pbs/surfels/blue_noise_metrics.hpp>
#include <pbs/surfels/ordering.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include "pbs/surfels/sphere_points.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <set>

namespace pbs {
namespace {

// Uniform in the unit square at z = 0 (area 1).
std::vector<glm::vec3> planePoints(std::size_t count, std::uint64_t seed) {
  SeededRandom rng(seed);
  std::vector<glm::vec3> points(count);
  for (glm::vec3& p : points) p = glm::vec3(rng.unit(), rng.unit(), 0.0);
  return points;
}

float squaredDistance(const glm::vec3& a, const glm::vec3& b) {
  const glm::vec3 d = a - b;
  return glm::dot(d, d);
}

// Squared distance of `p` to the nearest of `chosen` by a linear scan.
float nearestChosen(std::span<const glm::vec3> points, const std::vector<std::uint32_t>& chosen, const glm::vec3& p) {
  float best = std::numeric_limits<float>::infinity();
  for (std::uint32_t c : chosen) best = std::min(best, squaredDistance(points[c], p));
  return best;
}

// The greedy permutation in O(n²): same first draw, ties to the lower index.
std::vector<std::uint32_t> bruteFarthest(std::span<const glm::vec3> points, std::uint32_t max, std::uint64_t seed) {
  std::vector<std::uint32_t> order;
  if (points.empty() || max == 0) return order;
  SeededRandom rng(seed);
  order.push_back(static_cast<std::uint32_t>(rng.below(points.size())));
  std::vector<float> distance(points.size());
  std::vector<bool> taken(points.size(), false);
  taken[order[0]] = true;
  for (std::size_t i = 0; i < points.size(); ++i) distance[i] = squaredDistance(points[i], points[order[0]]);
  while (order.size() < std::min<std::size_t>(max, points.size())) {
    std::uint32_t best = 0;
    float bestD = -1.0f;
    for (std::uint32_t i = 0; i < points.size(); ++i) {
      if (!taken[i] && distance[i] > bestD) bestD = distance[i], best = i;
    }
    order.push_back(best);
    taken[best] = true;
    for (std::size_t i = 0; i < points.size(); ++i) {
      distance[i] = std::min(distance[i], squaredDistance(points[i], points[best]));
    }
  }
  return order;
}

// Dart throwing by its definition with linear-scan distances and the same draws as orderDart.
std::vector<std::uint32_t> bruteDart(std::span<const glm::vec3> points, std::uint32_t max, std::uint64_t seed,
                                     std::uint32_t candidates) {
  std::vector<std::uint32_t> order, pool(points.size());
  if (points.empty() || max == 0) return order;
  for (std::uint32_t i = 0; i < pool.size(); ++i) pool[i] = i;
  SeededRandom rng(seed);
  const auto take = [&pool](std::size_t pos) {
    pool[pos] = pool.back();
    pool.pop_back();
  };
  const std::size_t first = rng.below(pool.size());
  order.push_back(pool[first]);
  take(first);
  while (order.size() < max && !pool.empty()) {
    std::size_t farPos = 0, nearPos = 0;
    float farD = -1.0f, nearD = std::numeric_limits<float>::infinity();
    for (std::uint32_t c = 0; c < candidates; ++c) {
      const std::size_t pos = rng.below(pool.size());
      const float d = nearestChosen(points, order, points[pool[pos]]);
      if (d > farD || (d == farD && pool[pos] < pool[farPos])) farD = d, farPos = pos;
      if (d < nearD || (d == nearD && pool[pos] < pool[nearPos])) nearD = d, nearPos = pos;
    }
    order.push_back(pool[farPos]);
    take(std::max(farPos, nearPos));
    if (farPos != nearPos) take(std::min(farPos, nearPos));
  }
  return order;
}

void expectDistinctIndices(const std::vector<std::uint32_t>& order, std::size_t n) {
  std::set<std::uint32_t> seen;
  for (std::uint32_t i : order) {
    ASSERT_LT(i, n);
    ASSERT_TRUE(seen.insert(i).second) << "repeated index " << i;
  }
}

TEST(Ordering, PrefixesArePermutationsWithoutRepeats) {
  const auto points = uniformSpherePoints(3000, 7);
  for (std::uint32_t max : {0u, 1u, 1000u, 5000u}) {
    const auto random = orderRandom(points, max, 3);
    const auto farthest = orderFarthest(points, max, 3);
    const auto dart = orderDart(points, max, 3, 50);
    EXPECT_EQ(random.size(), std::min<std::size_t>(max, points.size()));
    EXPECT_EQ(farthest.size(), std::min<std::size_t>(max, points.size()));
    EXPECT_LE(dart.size(), std::min<std::size_t>(max, points.size()));
    expectDistinctIndices(random, points.size());
    expectDistinctIndices(farthest, points.size());
    expectDistinctIndices(dart, points.size());
  }
}

TEST(Ordering, FarthestIsTheExactGreedyPermutation) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const auto sphere = uniformSpherePoints(2000, seed);
    EXPECT_EQ(orderFarthest(sphere, 2000, seed), bruteFarthest(sphere, 2000, seed));
    const auto plane = planePoints(2000, seed + 10);
    EXPECT_EQ(orderFarthest(plane, 700, seed), bruteFarthest(plane, 700, seed));
  }
}

TEST(Ordering, DartFollowsItsDefinition) {
  for (std::uint64_t seed : {1u, 5u}) {
    const auto points = uniformSpherePoints(2000, seed);
    EXPECT_EQ(orderDart(points, 600, seed, 20), bruteDart(points, 600, seed, 20));
    // Until the pool runs dry: each round takes one and drops one.
    const auto all = orderDart(points, 5000, seed, 8);
    EXPECT_EQ(all, bruteDart(points, 5000, seed, 8));
    EXPECT_GE(all.size(), 1000u);
  }
}

TEST(Ordering, DeterministicForASeed) {
  const auto points = uniformSpherePoints(5000, 11);
  EXPECT_EQ(orderFarthest(points, 1000, 4), orderFarthest(points, 1000, 4));
  EXPECT_EQ(orderDart(points, 1000, 4), orderDart(points, 1000, 4));
  EXPECT_EQ(orderRandom(points, 1000, 4), orderRandom(points, 1000, 4));
  EXPECT_NE(orderFarthest(points, 1000, 4), orderFarthest(points, 1000, 5));
  EXPECT_NE(orderDart(points, 1000, 4), orderDart(points, 1000, 5));
  EXPECT_NE(orderRandom(points, 1000, 4), orderRandom(points, 1000, 5));
}

TEST(BlueNoiseMetrics, RhoRangesOnASphere) {
  const auto points = uniformSpherePoints(20000, 21);
  const double area = 4.0 * std::numbers::pi;
  const BlueNoiseSummary farthest = summarizeBlueNoise(points, orderFarthest(points, 5000, 1), area);
  const BlueNoiseSummary dart = summarizeBlueNoise(points, orderDart(points, 5000, 1), area);
  const BlueNoiseSummary random = summarizeBlueNoise(points, orderRandom(points, 5000, 1), area);
  EXPECT_GE(farthest.rhoMin, 0.6);
  EXPECT_GE(farthest.rhoMean, farthest.rhoMin);
  EXPECT_LE(farthest.rhoMean, 1.0);
  EXPECT_GE(dart.rhoMin, 0.4);
  EXPECT_LT(random.rhoMin, 0.2);
}

TEST(BlueNoiseMetrics, RhoRangesOnAPlanePatch) {
  const auto points = planePoints(20000, 22);
  const BlueNoiseSummary farthest = summarizeBlueNoise(points, orderFarthest(points, 5000, 1), 1.0);
  const BlueNoiseSummary random = summarizeBlueNoise(points, orderRandom(points, 5000, 1), 1.0);
  EXPECT_GE(farthest.rhoMin, 0.6);
  EXPECT_LT(random.rhoMin, 0.2);
}

TEST(BlueNoiseMetrics, MinDistancesAreTheRunningMinimum) {
  const auto points = planePoints(500, 3);
  const auto order = orderRandom(points, 500, 9);
  const auto minDistance = prefixMinDistances(points, order);
  ASSERT_EQ(minDistance.size(), order.size());
  EXPECT_TRUE(std::isinf(minDistance[0]));
  double running = std::numeric_limits<double>::infinity();
  for (std::size_t k = 1; k < order.size(); ++k) {
    for (std::size_t j = 0; j < k; ++j) {
      running = std::min(running, std::sqrt(double(squaredDistance(points[order[k]], points[order[j]]))));
    }
    EXPECT_NEAR(minDistance[k], running, 1e-6);
  }
}

TEST(BlueNoiseMetrics, MeanNearestNeighbourOfAGrid) {
  std::vector<glm::vec3> points;
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 20; ++x) points.emplace_back(0.5f * x, 0.5f * y, 2.0f);
  }
  const auto order = orderRandom(points, 400, 1);
  EXPECT_NEAR(meanNearestNeighbourDistance(points, order, 400), 0.5, 1e-6);
  EXPECT_EQ(meanNearestNeighbourDistance(points, order, 1), 0.0);
}

// Points crowded into a few small clusters of a large box, and one far outlier: the grid shrinks its cells
// to the clusters, and a query whose nearest point lies hundreds of cells away reads every point instead.
// Both must leave the exact nearest distances, so the mean is the brute force's to the bit.
TEST(BlueNoiseMetrics, MeanNearestNeighbourOfCrowdedClustersIsExact) {
  SeededRandom rng(12);
  std::vector<glm::vec3> points;
  for (int cluster = 0; cluster < 6; ++cluster) {
    const glm::vec3 centre(rng.unit() * 1000.0, rng.unit() * 1000.0, rng.unit() * 1000.0);
    for (const glm::vec3& p : uniformSpherePoints(500, std::uint64_t(cluster))) points.push_back(centre + 0.5f * p);
  }
  points.emplace_back(-5000.0f, 0.0f, 0.0f);
  const auto order = orderRandom(points, std::uint32_t(points.size()), 4);
  for (std::size_t count : {std::size_t(40), points.size()}) {
    double sum = 0.0;
    for (std::size_t k = 0; k < count; ++k) {
      float nearest = std::numeric_limits<float>::infinity();
      for (std::size_t j = 0; j < count; ++j)
        if (j != k) nearest = std::min(nearest, squaredDistance(points[order[j]], points[order[k]]));
      sum += std::sqrt(double(nearest));
    }
    EXPECT_EQ(meanNearestNeighbourDistance(points, order, count), sum / double(count)) << count;
  }
}

// The mean over all points by the brute force, in the order's order (the sum rounds the same way).
double bruteMeanNearest(std::span<const glm::vec3> points) {
  double sum = 0.0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    float nearest = std::numeric_limits<float>::infinity();
    for (std::size_t j = 0; j < points.size(); ++j)
      if (j != k) nearest = std::min(nearest, squaredDistance(points[j], points[k]));
    sum += std::sqrt(double(nearest));
  }
  return sum / double(points.size());
}

// Every point's nearest neighbour is found cell by cell, with outliers compared with every point (a few) or
// searched in shells (many), and crowded cells searched in shells: each kind of set below takes one of
// those paths, and each must give the brute force's mean to the bit.
TEST(BlueNoiseMetrics, MeanNearestNeighbourIsExactOnEveryKindOfSet) {
  const auto identity = [](std::size_t n) {
    std::vector<std::uint32_t> order(n);
    for (std::uint32_t i = 0; i < n; ++i) order[i] = i;
    return order;
  };
  const auto shifted = [](std::vector<glm::vec3> points, const glm::vec3& by) {
    for (glm::vec3& p : points) p += by;
    return points;
  };
  std::vector<std::pair<std::string, std::vector<glm::vec3>>> sets;
  // Both sides of a surface ordered apart, as surfelize's orderingPositions places them.
  std::vector<glm::vec3> sides = uniformSpherePoints(1500, 1);
  for (const glm::vec3& p : uniformSpherePoints(1500, 2)) sides.push_back(p + glm::vec3(6.0f, 0.0f, 0.0f));
  sets.emplace_back("two sides", sides);
  std::vector<glm::vec3> fewOutliers = planePoints(2000, 3);
  for (int i = 0; i < 10; ++i) fewOutliers.emplace_back(50.0f * float(i), -40.0f, 7.0f);
  sets.emplace_back("a few outliers", fewOutliers);
  std::vector<glm::vec3> manyOutliers = planePoints(2000, 4);
  for (const glm::vec3& p : uniformSpherePoints(300, 5)) manyOutliers.push_back(100.0f * p);
  sets.emplace_back("many outliers", manyOutliers);
  std::vector<glm::vec3> stacked;
  for (std::size_t i = 0; i < 1000; ++i) stacked.emplace_back(float(i % 5), 0.5f * float(i % 3), 0.0f);
  sets.emplace_back("points stacked 67 deep", stacked);
  sets.emplace_back("far from the origin", shifted(planePoints(1000, 6), glm::vec3(3.0e6f, -2.0e6f, 1.0e6f)));
  std::vector<glm::vec3> line;
  for (int i = 0; i < 500; ++i) line.emplace_back(0.001f * float(i * i % 997), 0.0f, 0.0f);
  sets.emplace_back("a line", line);
  std::vector<glm::vec3> tiny = planePoints(500, 7);
  for (glm::vec3& p : tiny) p *= 1e-20f;
  sets.emplace_back("a box of 1e-20", tiny);
  for (const auto& [name, points] : sets)
    EXPECT_EQ(meanNearestNeighbourDistance(points, identity(points.size()), points.size()), bruteMeanNearest(points))
        << name;
}

TEST(StiffInputs, EmptyInput) {
  const std::vector<glm::vec3> none;
  EXPECT_TRUE(orderRandom(none, 10, 1).empty());
  EXPECT_TRUE(orderDart(none, 10, 1).empty());
  EXPECT_TRUE(orderFarthest(none, 10, 1).empty());
  EXPECT_TRUE(prefixMinDistances(none, {}).empty());
  const BlueNoiseSummary summary = summarizeBlueNoise(none, {}, 1.0);
  EXPECT_EQ(summary.rhoMin, 0.0);
  EXPECT_EQ(summary.rhoMean, 0.0);
}

TEST(StiffInputs, AllPointsCoincident) {
  const std::vector<glm::vec3> points(1000, glm::vec3(0.25f, -3.0f, 7.0f));
  const auto farthest = orderFarthest(points, 300, 2);
  const auto dart = orderDart(points, 300, 2);
  ASSERT_EQ(farthest.size(), 300u);
  ASSERT_EQ(dart.size(), 300u);
  expectDistinctIndices(dart, points.size());
  EXPECT_EQ(farthest, bruteFarthest(points, 300, 2));
  // Every distance ties at 0, so after the random first point the rest come in index order.
  EXPECT_TRUE(std::is_sorted(farthest.begin() + 1, farthest.end()));
  const auto minDistance = prefixMinDistances(points, farthest);
  for (std::size_t k = 1; k < minDistance.size(); ++k) EXPECT_EQ(minDistance[k], 0.0);
  const BlueNoiseSummary summary = summarizeBlueNoise(points, farthest, 1.0);
  EXPECT_EQ(summary.rhoMin, 0.0);
  EXPECT_EQ(summary.rhoMean, 0.0);
  EXPECT_EQ(meanNearestNeighbourDistance(points, farthest, 300), 0.0);
}

TEST(StiffInputs, CollinearEvenlySpaced) {
  std::vector<glm::vec3> points;
  for (int i = 0; i < 1024; ++i) points.emplace_back(0.0f, 0.125f * i, 0.0f);
  EXPECT_EQ(orderFarthest(points, 1024, 6), bruteFarthest(points, 1024, 6));
  EXPECT_EQ(orderDart(points, 300, 6, 30), bruteDart(points, 300, 6, 30));
  const auto minDistance = prefixMinDistances(points, orderFarthest(points, 1024, 6));
  EXPECT_DOUBLE_EQ(minDistance.back(), 0.125);
}

// A lattice with every point twice, shuffled: many exactly equal distances, duplicates and interleaved
// indices within one grid cell (coarse cells for a short order, fine ones for the whole pool), where
// the lowest index must win each tie.
TEST(StiffInputs, LatticeTiesGoToTheLowestIndex) {
  std::vector<glm::vec3> points;
  for (int z = 0; z < 10; ++z)
    for (int y = 0; y < 10; ++y)
      for (int x = 0; x < 10; ++x) points.insert(points.end(), 2, glm::vec3(x, y, z));
  SeededRandom rng(4);
  for (std::size_t i = points.size() - 1; i > 0; --i) std::swap(points[i], points[rng.below(i + 1)]);
  for (std::uint32_t max : {16u, 200u, 2000u})
    for (std::uint64_t seed : {1u, 2u}) EXPECT_EQ(orderFarthest(points, max, seed), bruteFarthest(points, max, seed));
}

TEST(StiffInputs, TwoClustersFarApart) {
  auto points = uniformSpherePoints(600, 8);
  const auto other = uniformSpherePoints(600, 9);
  for (const glm::vec3& p : other) points.push_back(p * 0.01f + glm::vec3(1e4f, 0.0f, 0.0f));
  const auto farthest = orderFarthest(points, 1200, 3);
  EXPECT_EQ(farthest, bruteFarthest(points, 1200, 3));
  EXPECT_NE(farthest[0] < 600, farthest[1] < 600);  // the second point is in the other cluster
  EXPECT_EQ(orderDart(points, 400, 3, 40), bruteDart(points, 400, 3, 40));
  for (double d : prefixMinDistances(points, farthest)) EXPECT_FALSE(std::isnan(d));
}

}  // namespace
}  // namespace pbs
