// Stiff and extreme inputs for the orderings and the blue-noise metrics: degenerate, far, tiny, huge,
// non-finite. Every case ends with a defined, documented result (ordering.hpp, blue_noise_metrics.hpp).
#include <pbs/surfels/blue_noise_metrics.hpp>
#include <pbs/surfels/ordering.hpp>
#include <pbs/surfels/sphere_points.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <stdexcept>
#include <tuple>

namespace pbs {
namespace {

using Order = std::vector<std::uint32_t>;

// Distinct indices into n points.
void expectDistinct(const Order& order, std::size_t n) {
  std::set<std::uint32_t> seen;
  for (std::uint32_t i : order) {
    ASSERT_LT(i, n);
    ASSERT_TRUE(seen.insert(i).second) << "repeated index " << i;
  }
}

// The three orderings on `points`, each checked against the contract: farthest and random return
// min(max, n) distinct indices, dart at most that many and at least one when there is a point.
struct Orders {
  Order farthest, dart, random;
};
Orders orderAll(std::span<const glm::vec3> points, std::uint32_t max, std::uint64_t seed) {
  Orders orders{orderFarthest(points, max, seed), orderDart(points, max, seed), orderRandom(points, max, seed)};
  const std::size_t expected = std::min<std::size_t>(max, points.size());
  EXPECT_EQ(orders.farthest.size(), expected);
  EXPECT_EQ(orders.random.size(), expected);
  EXPECT_LE(orders.dart.size(), expected);
  if (expected > 0) {
    EXPECT_GE(orders.dart.size(), 1u);
  }
  expectDistinct(orders.farthest, points.size());
  expectDistinct(orders.dart, points.size());
  expectDistinct(orders.random, points.size());
  return orders;
}

void expectFiniteSummary(const BlueNoiseSummary& summary) {
  EXPECT_TRUE(std::isfinite(summary.rhoMin));
  EXPECT_TRUE(std::isfinite(summary.rhoMean));
  EXPECT_GE(summary.rhoMin, 0.0);
  EXPECT_GE(summary.rhoMean, summary.rhoMin);
}

std::vector<glm::vec3> scaled(std::span<const glm::vec3> points, float scale) {
  std::vector<glm::vec3> result(points.begin(), points.end());
  for (glm::vec3& p : result) p *= scale;
  return result;
}

TEST(OrderingStiff, TenThousandCoincidentPoints) {
  const std::vector<glm::vec3> points(10000, glm::vec3(1.5f, -2.0f, 1e3f));
  const Orders orders = orderAll(points, 10000, 4);
  // Every distance ties at 0: after the random first point the rest come in index order (and farthest
  // takes them in one pass instead of rescanning the one grid cell per point).
  Order expected{orders.farthest[0]};
  for (std::uint32_t i = 0; i < 10000; ++i)
    if (i != orders.farthest[0]) expected.push_back(i);
  EXPECT_EQ(orders.farthest, expected);
  // Dart takes one and drops one per round: about half the pool.
  EXPECT_GE(orders.dart.size(), 5000u);
  for (const Order* order : {&orders.farthest, &orders.dart, &orders.random}) {
    const std::vector<double> minDistance = prefixMinDistances(points, *order);
    ASSERT_EQ(minDistance.size(), order->size());
    EXPECT_TRUE(std::isinf(minDistance[0]));
    for (std::size_t k = 1; k < minDistance.size(); ++k) ASSERT_EQ(minDistance[k], 0.0);
    const BlueNoiseSummary summary = summarizeBlueNoise(points, *order, 1.0);
    EXPECT_EQ(summary.rhoMin, 0.0);
    EXPECT_EQ(summary.rhoMean, 0.0);
    EXPECT_EQ(meanNearestNeighbourDistance(points, *order, order->size()), 0.0);
  }
}

TEST(OrderingStiff, CollinearRandomPoints) {
  SeededRandom rng(3);
  std::vector<glm::vec3> points(5000);
  for (glm::vec3& p : points) p = glm::vec3(2.0f, -1.0f, 0.5f) * float(rng.unit()) + glm::vec3(1.0f, 0.0f, 0.0f);
  const Orders orders = orderAll(points, 2000, 5);
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (const glm::vec3& p : points) lo = std::min(lo, p.x), hi = std::max(hi, p.x);
  // The farthest point from any first point is an end of the segment.
  const float second = points[orders.farthest[1]].x;
  EXPECT_TRUE(second == lo || second == hi);
  // Segment length L = 2.29…: k greedy points keep at least L / (4k) apart (half the ideal spacing, with slack).
  const double length = glm::length(glm::vec3(2.0f, -1.0f, 0.5f));
  const std::vector<double> minDistance = prefixMinDistances(points, orders.farthest);
  for (std::size_t k = 2; k <= 2000; k *= 2) EXPECT_GE(minDistance[k - 1], length / (4.0 * double(k))) << k;
  for (const Order* order : {&orders.farthest, &orders.dart, &orders.random}) {
    for (double d : prefixMinDistances(points, *order)) ASSERT_FALSE(std::isnan(d));
    // A line has no area: ρ is reported for the area the caller gives, here 1.
    expectFiniteSummary(summarizeBlueNoise(points, *order, 1.0));
  }
}

TEST(OrderingStiff, TwoClustersAMillionApart) {
  auto points = scaled(uniformSpherePoints(3000, 8), 100.0f);
  for (const glm::vec3& p : uniformSpherePoints(3000, 9)) points.push_back(p * 100.0f + glm::vec3(1e6f, 0.0f, 0.0f));
  const Orders orders = orderAll(points, 2000, 3);
  EXPECT_NE(orders.farthest[0] < 3000, orders.farthest[1] < 3000);  // the second point is in the other cluster
  // Two equal spheres: the greedy order alternates between them closely.
  const auto inFirst = std::count_if(orders.farthest.begin(), orders.farthest.end(), [](auto i) { return i < 3000; });
  EXPECT_NEAR(double(inFirst), 1000.0, 50.0);
  for (const Order* order : {&orders.farthest, &orders.dart, &orders.random}) {
    for (double d : prefixMinDistances(points, *order)) ASSERT_FALSE(std::isnan(d));
    expectFiniteSummary(summarizeBlueNoise(points, *order, 2.0 * 4.0 * std::numbers::pi * 1e4));
    EXPECT_TRUE(std::isfinite(meanNearestNeighbourDistance(points, *order, order->size())));
  }
}

TEST(OrderingStiff, FlatPatchInEachAxisPlane) {
  SeededRandom rng(12);
  for (int flatAxis = 0; flatAxis < 3; ++flatAxis) {
    std::vector<glm::vec3> points(20000);
    for (glm::vec3& p : points) {
      p = glm::vec3(float(rng.unit()), float(rng.unit()), float(rng.unit()));
      p[flatAxis] = 0.0f;  // a box of exactly zero thickness
    }
    const Orders orders = orderAll(points, 5000, 1);
    const BlueNoiseSummary farthest = summarizeBlueNoise(points, orders.farthest, 1.0);
    const BlueNoiseSummary dart = summarizeBlueNoise(points, orders.dart, 1.0);
    const BlueNoiseSummary random = summarizeBlueNoise(points, orders.random, 1.0);
    EXPECT_GE(farthest.rhoMin, 0.6) << flatAxis;
    EXPECT_LE(farthest.rhoMean, 1.0) << flatAxis;
    EXPECT_GE(dart.rhoMin, 0.4) << flatAxis;
    EXPECT_LT(random.rhoMin, 0.2) << flatAxis;
    expectFiniteSummary(random);
  }
}

// Float has 24 bits: at 1e6 its step is 0.0625, so a grid of 1e-3 spacing stored as absolute float
// positions collapses to a few distinct points. The orderings stay valid and d_min drops to 0 once the
// distinct positions are used up; stored relative to a nearby origin (as surfels are) the same grid
// keeps its spacing.
TEST(OrderingStiff, MillionFromTheOriginWithMillimetreSpacing) {
  std::vector<glm::vec3> absolute, relative;
  for (int y = 0; y < 100; ++y) {
    for (int x = 0; x < 100; ++x) {
      const glm::dvec3 offset(1e-3 * x, 1e-3 * y, 0.0);
      absolute.emplace_back(glm::dvec3(1e6) + offset);
      relative.emplace_back(offset);
    }
  }
  std::set<std::tuple<float, float, float>> distinct;
  for (const glm::vec3& p : absolute) distinct.emplace(p.x, p.y, p.z);
  ASSERT_LE(distinct.size(), 9u);  // rounding to multiples of 1/16 leaves at most 3 × 3 positions
  const Orders orders = orderAll(absolute, 10000, 7);
  const std::vector<double> minDistance = prefixMinDistances(absolute, orders.farthest);
  // The greedy order visits every distinct position first, then the duplicates at distance 0.
  for (std::size_t k = 1; k < distinct.size(); ++k) EXPECT_GE(minDistance[k], 0.0625) << k;
  for (std::size_t k = distinct.size(); k < minDistance.size(); ++k) ASSERT_EQ(minDistance[k], 0.0);
  expectFiniteSummary(summarizeBlueNoise(absolute, orders.farthest, 1e-2));

  const Order relativeOrder = orderFarthest(relative, 10000, 7);
  const std::vector<double> relativeMin = prefixMinDistances(relative, relativeOrder);
  EXPECT_NEAR(relativeMin.back(), 1e-3, 1e-7);
  // A square lattice: right after each finer level starts, d_min is a diagonal, so ρ dips to ~0.54.
  EXPECT_GE(summarizeBlueNoise(relative, relativeOrder, 0.099 * 0.099).rhoMin, 0.5);
}

// The orderings compare distances only, and ρ divides d_min by a spacing of the same unit: scaling the
// points scales nothing else. By a power of two (exact in float) the orders and ρ are identical. By
// 1e±6 the scaled points are rounded to float, which moves d_min (a difference of coordinates 100
// times larger) by up to ~1e-6 relative: ρ agrees to 1e-6 for farthest, 1e-5 for dart.
TEST(OrderingStiff, ScaleInvariance) {
  const auto sphere = uniformSpherePoints(20000, 31);
  const double area = 4.0 * std::numbers::pi;
  const Orders unit = orderAll(sphere, 4000, 2);
  const BlueNoiseSummary unitFarthest = summarizeBlueNoise(sphere, unit.farthest, area);
  const BlueNoiseSummary unitDart = summarizeBlueNoise(sphere, unit.dart, area);
  for (const float scale : {0x1p-20f, 0x1p20f, 1e-6f, 1e6f}) {
    const auto points = scaled(sphere, scale);
    const double scaledArea = area * double(scale) * double(scale);
    const Orders orders = orderAll(points, 4000, 2);
    EXPECT_EQ(orders.random, unit.random) << scale;
    const BlueNoiseSummary farthest = summarizeBlueNoise(points, orders.farthest, scaledArea);
    const BlueNoiseSummary dart = summarizeBlueNoise(points, orders.dart, scaledArea);
    const bool exact = std::exp2(std::round(std::log2(scale))) == scale;
    if (exact) {
      EXPECT_EQ(orders.farthest, unit.farthest) << scale;
      EXPECT_EQ(orders.dart, unit.dart) << scale;
    }
    const double tolerance = exact ? 1e-12 : 1e-6;
    EXPECT_NEAR(farthest.rhoMin, unitFarthest.rhoMin, tolerance * unitFarthest.rhoMin) << scale;
    EXPECT_NEAR(farthest.rhoMean, unitFarthest.rhoMean, tolerance * unitFarthest.rhoMean) << scale;
    EXPECT_NEAR(dart.rhoMin, unitDart.rhoMin, 10 * tolerance * unitDart.rhoMin) << scale;
    EXPECT_NEAR(dart.rhoMean, unitDart.rhoMean, 10 * tolerance * unitDart.rhoMean) << scale;
  }
}

// Spreads below float's smallest normal number: squared distances underflow to 0, so the points
// count as coincident (no grid of zero-sized cells, no endless cell-size loop), even for the largest max.
TEST(OrderingStiff, SubnormalSpreadCountsAsCoincident) {
  std::vector<glm::vec3> points;
  const float tiny = std::numeric_limits<float>::denorm_min();
  for (int i = 0; i < 2000; ++i) points.emplace_back(float(i) * tiny, 0.0f, -float(i % 7) * tiny);
  const Orders orders = orderAll(points, std::numeric_limits<std::uint32_t>::max(), 1);
  for (double d : prefixMinDistances(points, orders.farthest)) ASSERT_FALSE(std::isnan(d));
  const BlueNoiseSummary summary = summarizeBlueNoise(points, orders.farthest, 1e-80);
  EXPECT_EQ(summary.rhoMin, 0.0);  // d_min is 0: ρ is 0, not NaN
  EXPECT_EQ(summary.rhoMean, 0.0);
}

TEST(OrderingStiff, SinglePointEmptyInputAndMaxZero) {
  const std::vector<glm::vec3> one{glm::vec3(3.0f, 4.0f, 5.0f)};
  for (std::uint32_t max : {1u, 2u, 1000u}) {
    const Orders orders = orderAll(one, max, 9);
    EXPECT_EQ(orders.farthest, Order{0});
    EXPECT_EQ(orders.dart, Order{0});
    EXPECT_EQ(orders.random, Order{0});
  }
  const std::vector<double> minDistance = prefixMinDistances(one, Order{0});
  ASSERT_EQ(minDistance.size(), 1u);
  EXPECT_TRUE(std::isinf(minDistance[0]));
  EXPECT_EQ(summarizeBlueNoise(one, Order{0}, 1.0).rhoMin, 0.0);
  EXPECT_EQ(meanNearestNeighbourDistance(one, Order{0}, 1), 0.0);

  const std::vector<glm::vec3> none;
  EXPECT_TRUE(orderAll(none, 100, 1).farthest.empty());
  EXPECT_EQ(meanNearestNeighbourDistance(none, {}, 5), 0.0);
  EXPECT_EQ(summarizeBlueNoise(none, {}, 0.0).rhoMean, 0.0);

  const auto sphere = uniformSpherePoints(100, 1);
  const Orders none0 = orderAll(sphere, 0, 1);
  EXPECT_TRUE(none0.farthest.empty() && none0.dart.empty() && none0.random.empty());
}

TEST(OrderingStiff, MaxLargerThanThePool) {
  const auto points = uniformSpherePoints(1000, 5);
  for (std::uint32_t max : {1001u, 5000u, std::numeric_limits<std::uint32_t>::max()}) {
    const Orders orders = orderAll(points, max, 6);  // farthest and random: all 1000, a permutation
    // Dart drops a point per round, so it ends with the pool empty well before 1000.
    EXPECT_LT(orders.dart.size(), 1000u);
    EXPECT_GE(orders.dart.size(), 500u);
  }
}

// Non-finite coordinates have no distances: the distance-based orderings and the metrics throw
// std::invalid_argument (before any work) rather than order garbage; orderRandom never reads positions.
TEST(OrderingStiff, NonFinitePointsAreRejected) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (const glm::vec3 bad : {glm::vec3(nan, 0.0f, 0.0f), glm::vec3(0.0f, inf, 0.0f), glm::vec3(0.0f, 0.0f, -inf)}) {
    for (std::size_t where : {std::size_t(0), std::size_t(17), std::size_t(99)}) {
      auto points = uniformSpherePoints(100, 2);
      points[where] = bad;
      EXPECT_THROW(orderFarthest(points, 50, 1), std::invalid_argument);
      EXPECT_THROW(orderDart(points, 50, 1), std::invalid_argument);
      const Order random = orderRandom(points, 100, 1);
      EXPECT_EQ(random.size(), 100u);
      expectDistinct(random, points.size());
      EXPECT_THROW(prefixMinDistances(points, random), std::invalid_argument);
      EXPECT_THROW(summarizeBlueNoise(points, random, 1.0), std::invalid_argument);
      EXPECT_THROW(meanNearestNeighbourDistance(points, random, 100), std::invalid_argument);
    }
  }
  // Finite but so far apart that squared distances overflow float: rejected the same way.
  std::vector<glm::vec3> huge = uniformSpherePoints(100, 3);
  huge[5] = glm::vec3(1e30f, 0.0f, 0.0f);
  EXPECT_THROW(orderFarthest(huge, 50, 1), std::invalid_argument);
  EXPECT_THROW(orderDart(huge, 50, 1), std::invalid_argument);
  EXPECT_THROW(prefixMinDistances(huge, orderRandom(huge, 100, 1)), std::invalid_argument);
  // An order index outside the points is an error, not an out-of-bounds read.
  const auto points = uniformSpherePoints(10, 4);
  EXPECT_THROW(prefixMinDistances(points, Order{0, 10}), std::invalid_argument);
  EXPECT_THROW(meanNearestNeighbourDistance(points, Order{0, 10}, 2), std::invalid_argument);
}

TEST(OrderingStiff, AreaZeroNegativeOrNotANumber) {
  const auto points = uniformSpherePoints(2000, 6);
  const Order order = orderFarthest(points, 1000, 1);
  for (double area : {0.0, -1.0, -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
    const BlueNoiseSummary summary = summarizeBlueNoise(points, order, area);
    EXPECT_EQ(summary.rhoMin, 0.0) << area;
    EXPECT_EQ(summary.rhoMean, 0.0) << area;
    EXPECT_EQ(relativeRadius(0.1, 100, area), 0.0) << area;
  }
  EXPECT_EQ(relativeRadius(0.1, 0, 1.0), 0.0);
  EXPECT_EQ(relativeRadius(std::numeric_limits<double>::infinity(), 1, 1.0),
            std::numeric_limits<double>::infinity());  // k = 1 has no pair: d_min is +inf, and so is ρ
}

}  // namespace
}  // namespace pbs
