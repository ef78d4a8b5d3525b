// Pre-filtered surfel colours: insertion distances and the filtered colours against brute force, the
// first surfel's mean, a two-colour plane, thread-count independence and stiff inputs.
#include <pbs/raster/seeded_random.hpp>
#include <pbs/raster/thread_arena.hpp>
#include <pbs/surfels/ordering.hpp>
#include <pbs/surfels/prefilter_colors.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace pbs {
namespace {

constexpr SurfelOrdering kOrderings[] = {SurfelOrdering::Farthest, SurfelOrdering::Dart, SurfelOrdering::Random};

float squaredDistance(const glm::vec3& a, const glm::vec3& b) {
  const glm::vec3 d = a - b;
  return glm::dot(d, d);
}

// Random candidates with random opaque-ish colours: on the unit square (a surface, as captures give),
// in the unit cube (a volume), on the square with one far outlier, or in twelve tight clusters far
// apart (a city block's buildings); in the last two the box is far wider than the points' spacing.
enum class Layout { Plane, Cube, Outlier, Clusters };

std::vector<Surfel> randomCandidates(std::size_t count, Layout layout, std::uint64_t seed) {
  SeededRandom rng(seed);
  std::vector<Surfel> candidates(count);
  for (Surfel& s : candidates) {
    s.position = glm::vec3(rng.unit(), rng.unit(), layout == Layout::Cube ? rng.unit() : 0.0);
    s.normal = glm::vec3(0.0f, 0.0f, 1.0f);
    s.color = glm::u8vec4(rng.below(256), rng.below(256), rng.below(256), 26 + rng.below(230));
  }
  if (layout == Layout::Outlier) candidates.back().position = glm::vec3(1e6f, -3e5f, 2e5f);
  if (layout == Layout::Clusters) {
    std::vector<glm::vec3> centres(12);
    for (glm::vec3& c : centres) c = glm::vec3(rng.unit(), rng.unit(), rng.unit()) * 1000.0f;
    for (std::size_t i = 0; i < count; ++i)
      candidates[i].position = centres[i % centres.size()] + 0.01f * candidates[i].position;
  }
  return candidates;
}

std::vector<glm::vec3> positionsOf(const std::vector<Surfel>& candidates) {
  std::vector<glm::vec3> positions;
  for (const Surfel& s : candidates) positions.push_back(s.position);
  return positions;
}

// d(i) by its definition, with linear scans.
std::vector<float> bruteInsertionDistances(std::span<const glm::vec3> points, std::span<const std::uint32_t> order) {
  std::vector<float> distances;
  for (std::size_t i = 0; i < order.size(); ++i) {
    float best = std::numeric_limits<float>::infinity();
    for (std::size_t j = 0; j < i; ++j) best = std::min(best, squaredDistance(points[order[j]], points[order[i]]));
    distances.push_back(std::sqrt(best));
  }
  return distances;
}

// The filtered colours by their definition, unrounded: every candidate tested, in index order.
std::vector<glm::dvec4> bruteMeans(std::span<const Surfel> candidates, std::span<const std::uint32_t> order) {
  const std::vector<glm::vec3> positions = positionsOf({candidates.begin(), candidates.end()});
  const std::vector<float> distances = bruteInsertionDistances(positions, order);
  std::vector<glm::dvec4> means;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const float radiusSquared = distances[i] * distances[i];
    glm::dvec4 weighted(0.0);
    double weight = 0.0;
    for (const Surfel& c : candidates) {
      const float r2 = squaredDistance(c.position, candidates[order[i]].position);
      if (!(r2 <= radiusSquared)) continue;
      const double w = radiusSquared > 0.0f ? std::exp(-2.0f * (r2 / radiusSquared)) : 1.0f;
      weight += w;
      weighted += w * glm::dvec4(c.color);
    }
    means.push_back(weighted / weight);
  }
  return means;
}

// Each channel is the mean rounded to nearest. The filter's weights are within about 1e-6 of std::exp's
// and its sums run in float lanes before double, so a mean within 1e-3 of a .5 may round either way.
void expectRoundedMeans(const std::vector<glm::u8vec4>& colors, const std::vector<glm::dvec4>& means) {
  ASSERT_EQ(colors.size(), means.size());
  for (std::size_t i = 0; i < colors.size(); ++i)
    for (int c = 0; c < 4; ++c)
      ASSERT_LE(std::abs(double(colors[i][c]) - means[i][c]), 0.5 + 1e-3) << "surfel " << i << ", channel " << c;
}

TEST(InsertionDistances, MatchBruteForceForEveryOrdering) {
  for (Layout layout : {Layout::Plane, Layout::Cube, Layout::Outlier, Layout::Clusters}) {
    const std::vector<glm::vec3> points = positionsOf(randomCandidates(3000, layout, 11));
    for (SurfelOrdering ordering : kOrderings) {
      SCOPED_TRACE(std::string(orderingName(ordering)) + ", layout " + std::to_string(int(layout)));
      const std::vector<std::uint32_t> order = orderPoints(ordering, points, 700, 5);
      const std::vector<float> distances = insertionDistances(points, order);
      ASSERT_EQ(distances.size(), order.size());
      EXPECT_EQ(distances[0], std::numeric_limits<float>::infinity());
      EXPECT_EQ(distances, bruteInsertionDistances(points, order));
      // The farthest ordering places every point at least as far as any later one.
      if (ordering == SurfelOrdering::Farthest) {
        for (std::size_t i = 2; i < distances.size(); ++i) ASSERT_LE(distances[i], distances[i - 1]) << i;
      }
    }
  }
}

TEST(InsertionDistances, EmptyRepeatedAndOutOfRange) {
  const std::vector<glm::vec3> points = {{0, 0, 0}, {3, 4, 0}};
  EXPECT_TRUE(insertionDistances(points, {}).empty());
  const std::vector<std::uint32_t> order = {1, 0, 1};
  EXPECT_EQ(insertionDistances(points, order),
            (std::vector<float>{std::numeric_limits<float>::infinity(), 5.0f, 0.0f}));
  const std::vector<std::uint32_t> beyond = {0, 2};
  EXPECT_THROW(insertionDistances(points, beyond), std::invalid_argument);
  EXPECT_THROW(prefilteredColors(std::vector<Surfel>(2), beyond), std::invalid_argument);
  const std::vector<glm::vec3> nan = {{0, 0, 0}, {std::nanf(""), 0, 0}};
  EXPECT_THROW(insertionDistances(nan, order), std::invalid_argument);
}

TEST(PrefilteredColors, MatchBruteForce) {
  for (Layout layout : {Layout::Plane, Layout::Cube, Layout::Outlier, Layout::Clusters}) {
    const std::vector<Surfel> candidates = randomCandidates(1500, layout, 3);
    const std::vector<glm::vec3> points = positionsOf(candidates);
    for (SurfelOrdering ordering : kOrderings) {
      SCOPED_TRACE(std::string(orderingName(ordering)) + ", layout " + std::to_string(int(layout)));
      const std::vector<std::uint32_t> order = orderPoints(ordering, points, 400, 9);
      expectRoundedMeans(prefilteredColors(candidates, order), bruteMeans(candidates, order));
    }
  }
}

TEST(PrefilteredColors, FirstSurfelIsTheMeanOfAllCandidates) {
  // Half the candidates (0, 40, 200, 255), half (200, 40, 100, 255): the mean is (100, 40, 150, 255) exactly.
  std::vector<Surfel> candidates = randomCandidates(2000, Layout::Plane, 4);
  for (std::size_t i = 0; i < candidates.size(); ++i)
    candidates[i].color = i % 2 ? glm::u8vec4(0, 40, 200, 255) : glm::u8vec4(200, 40, 100, 255);
  for (SurfelOrdering ordering : kOrderings) {
    const std::vector<std::uint32_t> order = orderPoints(ordering, positionsOf(candidates), 100, 2);
    EXPECT_EQ(prefilteredColors(candidates, order).front(), glm::u8vec4(100, 40, 150, 255)) << orderingName(ordering);
  }
}

// The unit square, red where x < 0.5 and blue elsewhere: the first surfel stands for all of it (the
// mean), and a late surfel, whose neighbourhood is small, for its own side only unless it is near the
// edge between them.
TEST(PrefilteredColors, TwoColourPlaneGoesFromTheMeanToEachSide) {
  constexpr int kSide = 200;
  const glm::u8vec4 red(255, 0, 0, 255), blue(0, 0, 255, 255);
  std::vector<Surfel> candidates;
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x)
      candidates.push_back(
          {glm::vec3((x + 0.5f) / kSide, (y + 0.5f) / kSide, 0.0f), glm::vec3(0, 0, 1), x < kSide / 2 ? red : blue});
  const std::vector<glm::vec3> points = positionsOf(candidates);
  for (SurfelOrdering ordering : kOrderings) {
    SCOPED_TRACE(orderingName(ordering));
    const std::vector<std::uint32_t> order = orderPoints(ordering, points, 2000, 6);
    const std::vector<glm::u8vec4> colors = prefilteredColors(candidates, order);
    const std::vector<float> distances = insertionDistances(points, order);
    EXPECT_NEAR(colors[0].r, 127.5, 0.5);
    EXPECT_NEAR(colors[0].b, 127.5, 0.5);
    std::size_t pure = 0, late = 0;
    for (std::size_t i = order.size() / 2; i < order.size(); ++i) {
      ++late;
      const glm::vec3 p = points[order[i]];
      if (std::abs(p.x - 0.5f) <= distances[i]) continue;  // its neighbourhood crosses the edge
      ASSERT_EQ(colors[i], p.x < 0.5f ? red : blue) << "surfel " << i;
      ++pure;
    }
    // Late neighbourhoods are narrow: nearly every late surfel is away from the edge.
    EXPECT_GT(pure, late * 8 / 10);
  }
}

TEST(PrefilteredColors, BitIdenticalForOneAndTwoThreads) {
  const std::vector<Surfel> candidates = randomCandidates(40000, Layout::Plane, 8);
  const std::vector<glm::vec3> points = positionsOf(candidates);
  for (SurfelOrdering ordering : kOrderings) {
    const std::vector<std::uint32_t> order = orderPoints(ordering, points, 4000, 1);
    std::vector<glm::u8vec4> one, two;
    runWithThreads(1, [&] { one = prefilteredColors(candidates, order); });
    runWithThreads(2, [&] { two = prefilteredColors(candidates, order); });
    EXPECT_EQ(one, two) << orderingName(ordering);
  }
}

// Two places, two candidates each at exactly the same position, taken in the order a, b, a, b: the
// repeats have d = 0 and take the mean of their own place; b (d = |a − b|) weighs a's pair by e^−2.
TEST(PrefilteredColors, CoincidentCandidates) {
  const glm::vec3 a(0.0f), b(0.0f, 3.0f, 4.0f);
  const std::vector<Surfel> candidates = {
      {a, {}, {10, 20, 30, 40}}, {a, {}, {30, 20, 10, 60}}, {b, {}, {200, 100, 0, 250}}, {b, {}, {100, 50, 100, 200}}};
  const std::vector<std::uint32_t> order = {0, 2, 1, 3};
  EXPECT_EQ(insertionDistances(positionsOf(candidates), order),
            (std::vector<float>{std::numeric_limits<float>::infinity(), 5.0f, 0.0f, 0.0f}));
  const std::vector<glm::u8vec4> colors = prefilteredColors(candidates, order);
  ASSERT_EQ(colors.size(), 4u);
  EXPECT_EQ(colors[0], glm::u8vec4(85, 48, 35, 138));  // (340, 190, 140, 550) / 4, rounded
  const double far = std::exp(-2.0f);
  const glm::dvec4 mixed = (glm::dvec4(300, 150, 100, 450) + far * glm::dvec4(40, 40, 40, 100)) / (2.0 + 2.0 * far);
  for (int c = 0; c < 4; ++c) EXPECT_LE(std::abs(double(colors[1][c]) - mixed[c]), 0.5 + 1e-3) << c;
  EXPECT_EQ(colors[2], glm::u8vec4(20, 20, 20, 50));
  EXPECT_EQ(colors[3], glm::u8vec4(150, 75, 50, 225));

  // All candidates at one place: every surfel is their mean.
  std::vector<Surfel> same(500, Surfel{glm::vec3(7.0f), {}, {}});
  for (std::size_t i = 0; i < same.size(); ++i) same[i].color = glm::u8vec4(i % 2 ? 100 : 50);
  for (SurfelOrdering ordering : kOrderings) {
    const std::vector<std::uint32_t> order = orderPoints(ordering, positionsOf(same), 50, 3);
    for (const glm::u8vec4& c : prefilteredColors(same, order)) ASSERT_EQ(c, glm::u8vec4(75)) << orderingName(ordering);
  }
}

// Scaling every position by a power of two scales every squared distance exactly: the same colours,
// however tiny or huge the scale.
TEST(PrefilteredColors, ScaleFree) {
  const std::vector<Surfel> candidates = randomCandidates(3000, Layout::Cube, 12);
  const std::vector<std::uint32_t> order = orderPoints(SurfelOrdering::Farthest, positionsOf(candidates), 500, 4);
  const std::vector<glm::u8vec4> unit = prefilteredColors(candidates, order);
  for (float scale : {0x1p-30f, 0x1p-10f, 0x1p10f, 0x1p50f}) {
    std::vector<Surfel> scaled = candidates;
    for (Surfel& s : scaled) s.position *= scale;
    EXPECT_EQ(prefilteredColors(scaled, order), unit) << scale;
  }
}

TEST(PrefilteredColors, EmptyAndSingle) {
  EXPECT_TRUE(prefilteredColors({}, {}).empty());
  const std::vector<Surfel> one = {{glm::vec3(1.0f), {}, {1, 2, 3, 4}}};
  const std::vector<std::uint32_t> first = {0};
  EXPECT_EQ(prefilteredColors(one, first), (std::vector<glm::u8vec4>{{1, 2, 3, 4}}));
}

TEST(SurfelColors, NamesBothWays) {
  for (SurfelColors colors : {SurfelColors::Pixel, SurfelColors::Prefiltered})
    EXPECT_EQ(parseSurfelColors(surfelColorsName(colors)), colors);
  EXPECT_EQ(surfelColorsName(SurfelColors::Pixel), "pixel");
  EXPECT_EQ(surfelColorsName(SurfelColors::Prefiltered), "prefiltered");
  EXPECT_FALSE(parseSurfelColors("mean"));
}

}  // namespace
}  // namespace pbs
