// Tests of drawPoints: splat coverage and sizes, projection, depth order and ties, channels, determinism.
#include "pbs/raster/points.hpp"
#include "pbs/raster/thread_arena.hpp"

#include "test_fixtures.hpp"

#include <gtest/gtest.h>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

namespace pbs {
namespace {

using test::coveredPixels;
using test::PixelSet;
using test::windowCamera;

// The coverage rules of points.hpp evaluated literally over every pixel, for a point at window (x, y) of
// nominal size s (PointOptions::subPixel as `subPixel`). `ambiguous` is set when a pixel centre lies within
// `epsilon` of the splat's edge, where a last-ulp difference in the window position may flip the pixel.
struct ExpectedSplat {
  PixelSet pixels;
  bool ambiguous = false;
};

ExpectedSplat expectedSplat(double x, double y, float size, bool round, int width, int height, double epsilon = 0.0,
                            bool subPixel = false) {
  const double s = std::clamp(size, subPixel ? 0.0f : 1.0f, 4096.0f);
  const double half = s / 2.0;
  ExpectedSplat expected;
  for (int py = 0; py < height; ++py) {
    for (int px = 0; px < width; ++px) {
      const double cx = px + 0.5, cy = py + 0.5;
      bool inside;
      double margin;
      if (round) {
        const double dx = cx - x, dy = cy - y;
        const bool holding = !subPixel && px == std::floor(x) && py == std::floor(y);
        inside = dx * dx + dy * dy < half * half || holding;
        margin = std::abs(std::sqrt(dx * dx + dy * dy) - half);
      } else {
        inside = cx >= x - half && cx < x + half && cy >= y - half && cy < y + half;
        const double mx = std::min(std::abs(cx - (x - half)), std::abs(cx - (x + half)));
        const double my = std::min(std::abs(cy - (y - half)), std::abs(cy - (y + half)));
        margin = std::min(mx, my);
      }
      if (inside) expected.pixels.emplace(px, py);
      if (margin <= epsilon) expected.ambiguous = true;
    }
  }
  // A disc's holding pixel changes where the centre crosses a pixel edge.
  if (round && !subPixel && (std::abs(x - std::round(x)) <= epsilon || std::abs(y - std::round(y)) <= epsilon))
    expected.ambiguous = true;
  return expected;
}

struct OnePoint {
  glm::vec3 position;
  float size = 1.0f;
};

Framebuffer drawOne(const Camera& camera, const OnePoint& point, bool round, bool subPixel = false) {
  Framebuffer framebuffer = makeFramebuffer(camera.width, camera.height, 0);
  PointSet set;
  set.positions = std::span(&point.position, 1);
  set.pointSize = point.size;
  drawPoints(framebuffer, camera, std::span(&set, 1), PointOptions{.round = round, .subPixel = subPixel});
  return framebuffer;
}

std::size_t pixelIndex(const Framebuffer& framebuffer, int x, int y) {
  return std::size_t(y) * framebuffer.width + std::size_t(x);
}

TEST(RasterPoints, SquaresCoverTheirSideSquaredAtCentresAndCorners) {
  const Camera camera = windowCamera(32, 32);
  for (const float size : {1.0f, 2.0f, 3.0f, 4.0f}) {
    for (const glm::dvec2 centre : {glm::dvec2(10.5, 7.5), glm::dvec2(10.0, 7.0), glm::dvec2(10.25, 7.75)}) {
      SCOPED_TRACE(testing::Message() << "size " << size << " at " << centre.x << ", " << centre.y);
      const Framebuffer framebuffer = drawOne(camera, {glm::vec3(centre, -0.5), size}, false);
      const PixelSet covered = coveredPixels(framebuffer);
      EXPECT_EQ(covered.size(), std::size_t(size * size));
      EXPECT_EQ(covered, expectedSplat(centre.x, centre.y, size, false, 32, 32).pixels);
    }
  }
  // The half-open rule picks the pixels left of and above a corner: size 1 at (10, 7) is pixel (9, 6), size 2 at
  // the centre of (10, 7) is (9..10, 6..7).
  EXPECT_EQ(coveredPixels(drawOne(camera, {glm::vec3(10.0, 7.0, -0.5), 1.0f}, false)), (PixelSet{{9, 6}}));
  EXPECT_EQ(coveredPixels(drawOne(camera, {glm::vec3(10.5, 7.5, -0.5), 2.0f}, false)),
            (PixelSet{{9, 6}, {10, 6}, {9, 7}, {10, 7}}));
}

TEST(RasterPoints, DiscsMatchTheAnalyticSet) {
  const Camera camera = windowCamera(32, 32);
  for (const float size : {1.0f, 1.5f, 2.0f, 3.0f, 4.0f, 5.0f, 7.3f}) {
    for (const glm::dvec2 centre :
         {glm::dvec2(16.5, 15.5), glm::dvec2(16.0, 15.0), glm::dvec2(16.25, 15.75), glm::dvec2(16.5, 15.0)}) {
      SCOPED_TRACE(testing::Message() << "size " << size << " at " << centre.x << ", " << centre.y);
      const Framebuffer framebuffer = drawOne(camera, {glm::vec3(centre, -0.5), size}, true);
      EXPECT_EQ(coveredPixels(framebuffer), expectedSplat(centre.x, centre.y, size, true, 32, 32).pixels);
    }
  }
  // No pixel centre is strictly within 0.5 of a corner: a 1-pixel disc there keeps just the pixel holding it.
  EXPECT_EQ(coveredPixels(drawOne(camera, {glm::vec3(16.0, 15.0, -0.5), 1.0f}, true)), (PixelSet{{16, 15}}));
  // A 2-pixel disc on a pixel centre: the four neighbours are at distance exactly 1, not strictly within.
  EXPECT_EQ(coveredPixels(drawOne(camera, {glm::vec3(16.5, 15.5, -0.5), 2.0f}, true)), (PixelSet{{16, 15}}));
  // Size 3 on a corner: the 2 × 2 block around it; the next pixels are √(1.5² + 0.5²) > 1.5 away.
  EXPECT_EQ(coveredPixels(drawOne(camera, {glm::vec3(16.0, 15.0, -0.5), 3.0f}, true)).size(), 4u);
  // Size 4 on a corner: the 4 × 4 block minus its corners, √(1.5² + 1.5²) > 2 away.
  EXPECT_EQ(coveredPixels(drawOne(camera, {glm::vec3(16.0, 15.0, -0.5), 4.0f}, true)).size(), 12u);
}

TEST(RasterPoints, ZeroNegativeAndNonFiniteSizesDrawNothing) {
  const Camera camera = windowCamera(16, 16);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (const bool round : {false, true}) {
    for (const float size : {0.0f, -1.0f, -0.0f, nan, inf, -inf}) {
      SCOPED_TRACE(testing::Message() << "size " << size << (round ? " disc" : " square"));
      EXPECT_TRUE(coveredPixels(drawOne(camera, {glm::vec3(8.5, 8.5, -0.5), size}, round)).empty());
    }
  }
  // The same through per-point factors.
  const std::vector<glm::vec3> positions(4, glm::vec3(8.5, 8.5, -0.5));
  const std::vector<float> factors = {0.0f, -2.0f, nan, inf};
  Framebuffer framebuffer = makeFramebuffer(16, 16, 0);
  PointSet set;
  set.positions = positions;
  set.sizeFactors = factors;
  set.pointSize = 2.0f;
  drawPoints(framebuffer, camera, std::span(&set, 1));
  EXPECT_TRUE(coveredPixels(framebuffer).empty());
}

TEST(RasterPoints, SubPixelSizeDrawsOnePixel) {
  const Camera camera = windowCamera(16, 16);
  EXPECT_EQ(coveredPixels(drawOne(camera, {glm::vec3(10.3, 7.8, -0.5), 0.3f}, false)), (PixelSet{{10, 7}}));
  EXPECT_EQ(coveredPixels(drawOne(camera, {glm::vec3(10.3, 7.8, -0.5), 0.3f}, true)), (PixelSet{{10, 7}}));
  EXPECT_EQ(coveredPixels(drawOne(camera, {glm::vec3(10.0, 7.0, -0.5), 1e-6f}, false)), (PixelSet{{9, 6}}));
}

TEST(RasterPoints, SubPixelPointsCoverOnlyTheCentresInside) {
  const Camera camera = windowCamera(16, 16);
  for (const bool round : {false, true}) {
    for (const float size : {1e-6f, 0.3f, 0.5f, 0.99f, 1.0f, 2.5f}) {
      for (const glm::dvec2 centre :
           {glm::dvec2(10.5, 7.5), glm::dvec2(10.3, 7.8), glm::dvec2(10.0, 7.0), glm::dvec2(10.6, 7.45)}) {
        SCOPED_TRACE(testing::Message() << "size " << size << " at " << centre.x << ", " << centre.y
                                        << (round ? " disc" : " square"));
        EXPECT_EQ(coveredPixels(drawOne(camera, {glm::vec3(centre, -0.5), size}, round, true)),
                  expectedSplat(centre.x, centre.y, size, round, 16, 16, 0.0, true).pixels);
      }
    }
  }
  // A tiny point on a pixel centre keeps that pixel; off it, none.
  EXPECT_EQ(coveredPixels(drawOne(camera, {glm::vec3(10.5, 7.5, -0.5), 0.01f}, false, true)), (PixelSet{{10, 7}}));
  EXPECT_TRUE(coveredPixels(drawOne(camera, {glm::vec3(10.3, 7.8, -0.5), 0.3f}, true, true)).empty());
}

// Sub-pixel points sample like area: one point per pixel at offsets (i + ½)/16 of a 16 × 16 lattice, squares of
// side ½ cover the pixel for 8 of 16 offsets per axis, a quarter of the pixels (= side²), with or without
// per-point size factors.
TEST(RasterPoints, SubPixelSquaresCoverTheirAreaOfALattice) {
  const Camera camera = windowCamera(16, 16);
  std::vector<glm::vec3> positions;
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i) positions.emplace_back(i + (i + 0.5) / 16.0, j + (j + 0.5) / 16.0, -0.5);
  const std::vector<float> halves(positions.size(), 0.5f);
  for (const bool factors : {false, true}) {
    Framebuffer framebuffer = makeFramebuffer(16, 16, 0);
    PointSet set;
    set.positions = positions;
    set.pointSize = factors ? 1.0f : 0.5f;
    if (factors) set.sizeFactors = halves;
    drawPoints(framebuffer, camera, std::span(&set, 1), PointOptions{.subPixel = true});
    EXPECT_EQ(coveredPixels(framebuffer).size(), 64u) << (factors ? "factors" : "point size");
  }
}

TEST(RasterPoints, HugeSizesAreClampedTo4096) {
  // 4100 pixels wide: a 10000-pixel square centred at x = 2050 covers exactly columns [2, 4098).
  const Camera camera = windowCamera(4100, 4);
  for (const float size : {10000.0f, 5000.0f, 4096.0f}) {
    const Framebuffer framebuffer = drawOne(camera, {glm::vec3(2050.0, 2.0, -0.5), size}, false);
    const PixelSet covered = coveredPixels(framebuffer);
    ASSERT_EQ(covered.size(), 4096u * 4u) << "size " << size;
    EXPECT_EQ(covered.begin()->first, 2);
    EXPECT_EQ(covered.rbegin()->first, 4097);
  }
  // A disc of the clamped size still reaches 2048 pixels either side of its centre, but not 2049.
  const Framebuffer disc = drawOne(camera, {glm::vec3(2050.0, 2.0, -0.5), 1e9f}, true);
  EXPECT_TRUE(disc.covered(pixelIndex(disc, 2, 2)));
  EXPECT_TRUE(disc.covered(pixelIndex(disc, 4097, 2)));
  EXPECT_FALSE(disc.covered(pixelIndex(disc, 1, 2)));
  EXPECT_FALSE(disc.covered(pixelIndex(disc, 4098, 2)));
}

TEST(RasterPoints, SplatsAreClippedToTheViewport) {
  const Camera camera = windowCamera(16, 16);
  for (const bool round : {false, true}) {
    for (const glm::dvec2 centre : {glm::dvec2(-1.0, 5.5), glm::dvec2(15.5, 16.75), glm::dvec2(-1.5, -1.5),
                                    glm::dvec2(17.5, 17.5), glm::dvec2(-1.25, 17.0), glm::dvec2(-0.25, -0.25)}) {
      SCOPED_TRACE(testing::Message() << (round ? "disc" : "square") << " at " << centre.x << ", " << centre.y);
      const Framebuffer framebuffer = drawOne(camera, {glm::vec3(centre, -0.5), 5.0f}, round);
      EXPECT_EQ(coveredPixels(framebuffer), expectedSplat(centre.x, centre.y, 5.0f, round, 16, 16).pixels);
    }
  }
}

TEST(RasterPoints, RandomSplatsAroundTheBordersFollowTheRules) {
  const Camera camera = windowCamera(32, 16);
  std::mt19937 random(3);
  std::uniform_real_distribution<float> x(-6.0f, 38.0f), y(-6.0f, 22.0f), size(0.2f, 9.0f);
  for (int i = 0; i < 3000; ++i) {
    const OnePoint point{glm::vec3(x(random), y(random), -0.5f), size(random)};
    const bool round = i % 2 == 1;
    const Framebuffer framebuffer = drawOne(camera, point, round);
    const glm::dvec2 centre(point.position);
    ASSERT_EQ(coveredPixels(framebuffer), expectedSplat(centre.x, centre.y, point.size, round, 32, 16).pixels)
        << (round ? "disc" : "square") << " of size " << point.size << " at " << point.position.x << ", "
        << point.position.y;
  }
}

TEST(RasterPoints, LargeSplatsSpanningManyTilesCoverEveryPixelOnce) {
  const Camera camera = windowCamera(512, 256);
  for (const bool round : {false, true}) {
    const Framebuffer framebuffer = drawOne(camera, {glm::vec3(200.25, 130.5, -0.5), 300.0f}, round);
    EXPECT_EQ(coveredPixels(framebuffer), expectedSplat(200.25, 130.5, 300.0f, round, 512, 256).pixels);
  }
}

TEST(RasterPoints, SizeFactorsScaleThePointSize) {
  const Camera camera = windowCamera(64, 16);
  const std::vector<glm::vec3> positions = {{8.0, 8.0, -0.5}, {24.0, 8.0, -0.5}, {40.0, 8.0, -0.5}};
  const std::vector<float> factors = {0.5f, 1.0f, 2.0f};
  Framebuffer framebuffer = makeFramebuffer(64, 16, 0);
  PointSet set;
  set.positions = positions;
  set.sizeFactors = factors;
  set.pointSize = 2.0f;
  drawPoints(framebuffer, camera, std::span(&set, 1));
  PixelSet expected;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const PixelSet one = expectedSplat(positions[i].x, positions[i].y, 2.0f * factors[i], false, 64, 16).pixels;
    expected.insert(one.begin(), one.end());
  }
  EXPECT_EQ(coveredPixels(framebuffer), expected);
  EXPECT_EQ(expected.size(), 1u + 4u + 16u);
}

TEST(RasterPoints, DepthIsTheCentresWindowDepth) {
  const Camera camera = windowCamera(16, 16);
  const Framebuffer framebuffer = drawOne(camera, {glm::vec3(8.0, 8.0, -0.375), 4.0f}, false);
  for (const auto& [x, y] : coveredPixels(framebuffer))
    EXPECT_EQ(framebuffer.depth[pixelIndex(framebuffer, x, y)], 0.375f);
}

// Projection through general cameras and transforms, point by point against camera.hpp's windowFromClip.
void expectProjectionMatchesWindowFromClip(const Camera& camera, const glm::dmat4& worldFromObject, bool round,
                                           float size) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> coordinate(-1.5f, 1.5f);
  const glm::dmat4 clipFromObject = camera.clipFromWorld() * worldFromObject;
  Framebuffer framebuffer = makeFramebuffer(camera.width, camera.height, 0);
  int drawn = 0, ambiguous = 0;
  for (int i = 0; i < 400; ++i) {
    const glm::vec3 position(coordinate(random), coordinate(random), coordinate(random));
    const glm::dvec4 clip = clipFromObject * glm::dvec4(glm::dvec3(position), 1.0);
    const bool inRange = clip.w > 0.0 && clip.z >= -clip.w && clip.z <= clip.w;
    const glm::dvec3 window = inRange ? windowFromClip(camera, clip) : glm::dvec3(-1e9);
    const ExpectedSplat expected =
        expectedSplat(window.x, window.y, size, round, int(camera.width), int(camera.height), 1e-9);
    clearFramebuffer(framebuffer);
    PointSet set;
    set.positions = std::span(&position, 1);
    set.pointSize = size;
    set.worldFromObject = worldFromObject;
    drawPoints(framebuffer, camera, std::span(&set, 1), PointOptions{round});
    if (expected.ambiguous) {
      ++ambiguous;
      continue;
    }
    const PixelSet covered = coveredPixels(framebuffer);
    ASSERT_EQ(covered, expected.pixels) << "point " << i << " at window " << window.x << ", " << window.y;
    for (const auto& [x, y] : covered)
      EXPECT_FLOAT_EQ(framebuffer.depth[pixelIndex(framebuffer, x, y)], float(window.z));
    drawn += !covered.empty();
  }
  EXPECT_GT(drawn, 100);
  EXPECT_LT(ambiguous, 4);
}

TEST(RasterPoints, PerspectiveProjectionMatchesWindowFromClip) {
  const glm::dmat4 view = glm::lookAt(glm::dvec3(0.5, 1.0, 4.0), glm::dvec3(0.0), glm::dvec3(0.0, 1.0, 0.0));
  const Camera camera = perspectiveCamera(view, 0.9, 0.5, 20.0, 96, 64);
  const glm::dmat4 worldFromObject =
      glm::rotate(glm::translate(glm::dmat4(1.0), glm::dvec3(0.2, -0.1, 0.3)), 0.4, glm::dvec3(0.3, 1.0, 0.2));
  for (const bool round : {false, true})
    for (const float size : {1.0f, 3.0f, 4.5f}) {
      SCOPED_TRACE(testing::Message() << (round ? "disc " : "square ") << size);
      expectProjectionMatchesWindowFromClip(camera, worldFromObject, round, size);
    }
}

TEST(RasterPoints, OrthographicProjectionMatchesWindowFromClip) {
  const glm::dmat4 view = glm::lookAt(glm::dvec3(1.0, 2.0, 3.0), glm::dvec3(0.0), glm::dvec3(0.0, 1.0, 0.0));
  const Camera camera = orthographicCamera(view, -2.0, 2.5, -1.5, 1.7, 0.1, 8.0, 80, 72);
  const glm::dmat4 worldFromObject = glm::scale(glm::dmat4(1.0), glm::dvec3(1.2, 0.8, 1.0));
  for (const bool round : {false, true})
    for (const float size : {1.0f, 2.0f, 3.5f}) {
      SCOPED_TRACE(testing::Message() << (round ? "disc " : "square ") << size);
      expectProjectionMatchesWindowFromClip(camera, worldFromObject, round, size);
    }
}

TEST(RasterPoints, PointsOutsideNearFarOrBehindTheCameraAreDropped) {
  // Looking down −Z from the origin; near 1, far 10.
  const Camera camera = perspectiveCamera(glm::dmat4(1.0), 1.0, 1.0, 10.0, 32, 32);
  const auto drawsAt = [&](double z) {
    return !coveredPixels(drawOne(camera, {glm::vec3(0.0, 0.0, z), 3.0f}, false)).empty();
  };
  EXPECT_TRUE(drawsAt(-5.0));
  EXPECT_TRUE(drawsAt(-1.01));
  EXPECT_TRUE(drawsAt(-9.99));
  EXPECT_FALSE(drawsAt(-0.99));   // nearer than the near plane
  EXPECT_FALSE(drawsAt(-10.01));  // beyond the far plane
  EXPECT_FALSE(drawsAt(0.0));     // at the eye: w = 0
  EXPECT_FALSE(drawsAt(5.0));     // behind the camera: w < 0
  // Orthographic: depth range only.
  const Camera ortho = windowCamera(16, 16);
  EXPECT_TRUE(coveredPixels(drawOne(ortho, {glm::vec3(8.0, 8.0, 0.25), 1.0f}, false)).empty());
  EXPECT_TRUE(coveredPixels(drawOne(ortho, {glm::vec3(8.0, 8.0, -1.25), 1.0f}, false)).empty());
  // Non-finite positions are dropped as well.
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  EXPECT_TRUE(coveredPixels(drawOne(ortho, {glm::vec3(nan, 8.0, -0.5), 3.0f}, false)).empty());
  EXPECT_TRUE(coveredPixels(drawOne(ortho, {glm::vec3(8.0, inf, -0.5), 3.0f}, true)).empty());
}

// A framebuffer with every channel.
Framebuffer allChannels(std::uint32_t width, std::uint32_t height) {
  return makeFramebuffer(width, height, kChannelColor | kChannelPosition | kChannelNormal | kChannelIds);
}

TEST(RasterPoints, NearestPointWinsInEitherOrder) {
  const Camera camera = windowCamera(16, 16);
  for (const bool nearFirst : {true, false}) {
    std::vector<glm::vec3> positions = {{8.5, 8.5, -0.25}, {8.5, 8.5, -0.75}};
    if (!nearFirst) std::swap(positions[0], positions[1]);
    const std::vector<glm::u8vec4> colors = {{255, 0, 0, 255}, {0, 255, 0, 255}};
    const std::vector<glm::vec3> normals(2, glm::vec3(0, 0, 1));
    Framebuffer framebuffer = allChannels(16, 16);
    PointSet set;
    set.positions = positions;
    set.colors = colors;
    set.normals = normals;
    set.pointSize = 3.0f;
    drawPoints(framebuffer, camera, std::span(&set, 1));
    const std::size_t pixel = pixelIndex(framebuffer, 8, 8);
    EXPECT_EQ(framebuffer.depth[pixel], 0.25f);
    EXPECT_EQ(framebuffer.ids[pixel].primitive, nearFirst ? 0u : 1u);
    EXPECT_EQ(framebuffer.color[pixel], colors[nearFirst ? 0 : 1]);
  }
}

TEST(RasterPoints, EqualDepthGoesToTheEarlierSetAndIndex) {
  const Camera camera = windowCamera(64, 64);
  // Set 0 has 20000 copies of one point (many chunks) with sizes cycling through 1, 3, …, 13; set 1 one more
  // at the same depth, of size 20. Every pixel goes to the first point covering it, whatever the threads.
  const std::vector<glm::vec3> many(20000, glm::vec3(20.0, 20.0, -0.5));
  std::vector<float> factors(many.size());
  for (std::size_t i = 0; i < factors.size(); ++i) factors[i] = 0.5f + float(i % 7);
  const std::vector<glm::vec3> one = {glm::vec3(20.0, 20.0, -0.5)};
  for (const bool round : {false, true}) {
    for (const int threads : {1, 2, 5}) {
      Framebuffer framebuffer = makeFramebuffer(64, 64, kChannelIds);
      std::vector<PointSet> sets(2);
      sets[0].positions = many;
      sets[0].sizeFactors = factors;
      sets[0].pointSize = 2.0f;
      sets[0].nodeId = 10;
      sets[1].positions = one;
      sets[1].pointSize = 20.0f;
      sets[1].nodeId = 11;
      runWithThreads(threads, [&] { drawPoints(framebuffer, camera, sets, PointOptions{round}); });
      EXPECT_EQ(coveredPixels(framebuffer), expectedSplat(20.0, 20.0, 20.0f, round, 64, 64).pixels);
      for (const auto& [x, y] : coveredPixels(framebuffer)) {
        const PixelIds ids = framebuffer.ids[pixelIndex(framebuffer, x, y)];
        std::uint32_t expectedIndex = 0xffffffffu;
        for (std::uint32_t i = 0; i < 7 && expectedIndex == 0xffffffffu; ++i)
          if (expectedSplat(20.0, 20.0, 2.0f * factors[i], round, 64, 64).pixels.count({x, y})) expectedIndex = i;
        if (expectedIndex == 0xffffffffu) {
          EXPECT_EQ(ids.node, 11u);
          EXPECT_EQ(ids.primitive, 0u);
        } else {
          EXPECT_EQ(ids.node, 10u);
          EXPECT_EQ(ids.primitive, expectedIndex) << "pixel " << x << ", " << y;
        }
      }
    }
  }
}

TEST(RasterPoints, EqualDepthTiesHoldAcrossBatches) {
  // More points than one batch holds, all on one pixel at one depth: the first one wins.
  const Camera camera = windowCamera(8, 8);
  const std::vector<glm::vec3> positions((1u << 20) + 1000, glm::vec3(4.5, 4.5, -0.5));
  Framebuffer framebuffer = makeFramebuffer(8, 8, kChannelIds);
  PointSet set;
  set.positions = positions;
  runWithThreads(2, [&] { drawPoints(framebuffer, camera, std::span(&set, 1)); });
  EXPECT_EQ(framebuffer.ids[pixelIndex(framebuffer, 4, 4)].primitive, 0u);
  EXPECT_EQ(coveredPixels(framebuffer).size(), 1u);
}

TEST(RasterPoints, DrawsOverExistingDepthWithTheSameTest) {
  const Camera camera = windowCamera(16, 16);
  Framebuffer framebuffer = makeFramebuffer(16, 16, kChannelColor);
  std::fill(framebuffer.depth.begin(), framebuffer.depth.end(), 0.5f);
  const std::vector<glm::vec3> positions = {{4.5, 4.5, -0.5}, {8.5, 8.5, -0.75}, {12.5, 12.5, -0.25}};
  const std::vector<glm::u8vec4> colors(3, glm::u8vec4(9, 9, 9, 9));
  PointSet set;
  set.positions = positions;
  set.colors = colors;
  drawPoints(framebuffer, camera, std::span(&set, 1));
  EXPECT_EQ(framebuffer.color[pixelIndex(framebuffer, 4, 4)], glm::u8vec4(0));  // equal depth: existing stays
  EXPECT_EQ(framebuffer.color[pixelIndex(framebuffer, 8, 8)], glm::u8vec4(0));  // behind
  EXPECT_EQ(framebuffer.color[pixelIndex(framebuffer, 12, 12)], colors[2]);
  EXPECT_EQ(framebuffer.depth[pixelIndex(framebuffer, 12, 12)], 0.25f);
}

// 200k random points in four sets with every channel, duplicates for ties, mixed sizes and transforms; the last
// set has only 1-pixel points, which take the fast path.
struct RandomScene {
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::u8vec4> colors;
  std::vector<float> factors;
  std::vector<PointSet> sets;

  RandomScene() {
    std::mt19937 random(42);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), factor(0.2f, 3.0f);
    const std::size_t count = 200000;
    for (std::size_t i = 0; i < count; ++i) {
      // Every fifth point repeats an earlier one: equal depths in the same and in different sets.
      const bool repeat = i % 5 == 4;
      positions.push_back(repeat ? positions[i / 2] : glm::vec3(unit(random), unit(random), unit(random)));
      normals.push_back(glm::vec3(unit(random), unit(random), unit(random)));
      colors.push_back(glm::u8vec4(random(), random(), random(), 255));
      factors.push_back(i % 3 == 0 ? 1.0f : factor(random));
    }
    const std::size_t split[] = {0, 50000, 100000, 140000, count};
    for (int s = 0; s < 4; ++s) {
      PointSet set;
      const std::size_t first = split[s], size = split[s + 1] - split[s];
      set.positions = std::span(positions).subspan(first, size);
      set.normals = std::span(normals).subspan(first, size);
      set.colors = std::span(colors).subspan(first, size);
      if (s == 0 || s == 2) set.sizeFactors = std::span(factors).subspan(first, size);
      set.pointSize = s == 2 ? 0.8f : s == 3 ? 1.0f : 1.5f;
      set.worldFromObject = glm::rotate(glm::dmat4(1.0), 0.3 * s, glm::dvec3(0.0, 1.0, 0.0));
      set.nodeId = 100 + s;
      set.instanceId = 7;
      sets.push_back(set);
    }
  }
};

bool sameFramebuffer(const Framebuffer& a, const Framebuffer& b) {
  return a.depth == b.depth && a.color == b.color && a.position == b.position && a.normal == b.normal && a.ids == b.ids;
}

TEST(RasterPoints, ImageIsIdenticalForAnyThreadCount) {
  const RandomScene scene;
  const glm::dmat4 view = glm::lookAt(glm::dvec3(0.0, 0.5, 3.0), glm::dvec3(0.0), glm::dvec3(0.0, 1.0, 0.0));
  const Camera camera = perspectiveCamera(view, 0.8, 0.5, 10.0, 320, 240);
  for (const PointOptions options :
       {PointOptions{.round = false}, PointOptions{.round = true}, PointOptions{.round = false, .subPixel = true},
        PointOptions{.round = true, .subPixel = true}}) {
    SCOPED_TRACE(testing::Message() << (options.round ? "discs" : "squares")
                                    << (options.subPixel ? ", sub-pixel" : ""));
    std::vector<Framebuffer> images;
    for (const int threads : {1, 2, 5}) {
      images.push_back(makeFramebuffer(320, 240, kChannelColor | kChannelPosition | kChannelNormal | kChannelIds,
                                       glm::dvec3(0.1, 0.2, 0.3)));
      runWithThreads(threads, [&] { drawPoints(images.back(), camera, scene.sets, options); });
    }
    EXPECT_GT(coveredPixels(images[0]).size(), 320u * 240u / (options.subPixel ? 4 : 2));
    EXPECT_TRUE(sameFramebuffer(images[0], images[1]));
    EXPECT_TRUE(sameFramebuffer(images[0], images[2]));
  }
}

TEST(RasterPoints, OnePixelFastPathMatchesTheGeneralPath) {
  // The same 1-pixel points, once alone (the fast path) and once with a larger point behind the camera in the
  // same set, which sends every chunk through the general path.
  const RandomScene scene;
  const std::span<const glm::vec3> positions = std::span(scene.positions).first(100000);
  std::vector<glm::vec3> withLarge(positions.begin(), positions.end());
  withLarge.push_back(glm::vec3(0.0f, 0.0f, 10.0f));
  std::vector<float> factors(withLarge.size(), 1.0f);
  factors.back() = 1.5f;
  const glm::dmat4 view = glm::lookAt(glm::dvec3(0.0, 0.5, 3.0), glm::dvec3(0.0), glm::dvec3(0.0, 1.0, 0.0));
  const Camera camera = perspectiveCamera(view, 0.8, 0.5, 10.0, 400, 300);
  for (const bool round : {false, true}) {
    Framebuffer fast = makeFramebuffer(400, 300, kChannelIds), general = makeFramebuffer(400, 300, kChannelIds);
    PointSet set;
    set.positions = positions;
    drawPoints(fast, camera, std::span(&set, 1), PointOptions{round});
    set.positions = withLarge;
    set.sizeFactors = factors;
    drawPoints(general, camera, std::span(&set, 1), PointOptions{round});
    EXPECT_GT(coveredPixels(fast).size(), 400u * 300u / 4);
    EXPECT_TRUE(sameFramebuffer(fast, general)) << (round ? "discs" : "squares");
  }
}

TEST(RasterPoints, ColourOnlyAndFullChannelDrawsAgree) {
  // The colour-only framebuffer takes a shorter path; it must pick the same winners.
  const RandomScene scene;
  const glm::dmat4 view = glm::lookAt(glm::dvec3(0.0, 0.5, 3.0), glm::dvec3(0.0), glm::dvec3(0.0, 1.0, 0.0));
  const Camera camera = perspectiveCamera(view, 0.8, 0.5, 10.0, 200, 150);
  Framebuffer colorOnly = makeFramebuffer(200, 150, kChannelColor);
  Framebuffer depthOnly = makeFramebuffer(200, 150, 0);
  Framebuffer full = allChannels(200, 150);
  drawPoints(colorOnly, camera, scene.sets);
  drawPoints(depthOnly, camera, scene.sets);
  drawPoints(full, camera, scene.sets);
  EXPECT_TRUE(colorOnly.depth == full.depth);
  EXPECT_TRUE(depthOnly.depth == full.depth);
  EXPECT_TRUE(colorOnly.color == full.color);
}

TEST(RasterPoints, ChannelsOfATransformedSet) {
  const glm::dmat4 view = glm::lookAt(glm::dvec3(0.0, 0.0, 5.0), glm::dvec3(0.0), glm::dvec3(0.0, 1.0, 0.0));
  const Camera camera = perspectiveCamera(view, 0.8, 0.5, 20.0, 128, 128);
  const glm::dmat4 worldFromObject = glm::scale(
      glm::rotate(glm::translate(glm::dmat4(1.0), glm::dvec3(0.3, -0.2, 0.5)), 0.7, glm::dvec3(1.0, 1.0, 0.0)),
      glm::dvec3(2.0, 0.5, 1.0));
  const glm::dvec3 origin(0.25, -0.5, 1.0);
  const std::vector<glm::vec3> positions = {{-0.5f, 0.0f, 0.0f}, {0.0f, 0.5f, 0.0f}, {0.5f, -0.5f, 0.2f}};
  const std::vector<glm::vec3> normals = {{0.0f, 0.0f, 1.0f}, {1.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 0.0f}};
  const std::vector<glm::u8vec4> colors = {{1, 2, 3, 4}, {5, 6, 7, 8}, {9, 10, 11, 12}};
  PointSet set;
  set.positions = positions;
  set.normals = normals;
  set.colors = colors;
  set.worldFromObject = worldFromObject;
  set.pointSize = 3.0f;
  set.nodeId = 42;
  set.instanceId = 9;
  Framebuffer framebuffer =
      makeFramebuffer(128, 128, kChannelColor | kChannelPosition | kChannelNormal | kChannelIds, origin);
  drawPoints(framebuffer, camera, std::span(&set, 1));

  const glm::dmat3 normalFromObject = glm::inverseTranspose(glm::dmat3(worldFromObject));
  for (std::uint32_t i = 0; i < positions.size(); ++i) {
    SCOPED_TRACE(testing::Message() << "point " << i);
    const glm::dvec3 world(worldFromObject * glm::dvec4(glm::dvec3(positions[i]), 1.0));
    const glm::dvec3 window = windowFromClip(camera, camera.clipFromWorld() * glm::dvec4(world, 1.0));
    const std::size_t pixel = pixelIndex(framebuffer, int(window.x), int(window.y));
    ASSERT_TRUE(framebuffer.covered(pixel));
    EXPECT_EQ(framebuffer.ids[pixel], (PixelIds{42, 9, i}));
    EXPECT_EQ(framebuffer.color[pixel], colors[i]);
    const glm::vec3 position = framebuffer.position[pixel];
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(position[k], world[k] - origin[k], 1e-5);
    const glm::vec3 normal = framebuffer.normal[pixel];
    const glm::dvec3 expectedNormal =
        normals[i] == glm::vec3(0.0f) ? glm::dvec3(0.0) : glm::normalize(normalFromObject * glm::dvec3(normals[i]));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(normal[k], expectedNormal[k], 1e-6);
  }
}

TEST(RasterPoints, DegenerateTransformsGiveZeroNormalsNotNaN) {
  const Camera camera = windowCamera(16, 16);
  const std::vector<glm::vec3> positions = {{8.5f, 8.5f, -0.5f}};
  const std::vector<glm::vec3> normals = {{0.0f, 0.0f, 1.0f}};
  PointSet set;
  set.positions = positions;
  set.normals = normals;
  // Flattening z makes the matrix singular: no inverse transpose, so no normal.
  set.worldFromObject = glm::scale(glm::dmat4(1.0), glm::dvec3(1.0, 1.0, 0.0));
  Framebuffer framebuffer = makeFramebuffer(16, 16, kChannelNormal);
  drawPoints(framebuffer, camera, std::span(&set, 1));
  const std::size_t pixel = pixelIndex(framebuffer, 8, 8);
  ASSERT_TRUE(framebuffer.covered(pixel));
  EXPECT_EQ(framebuffer.normal[pixel], glm::vec3(0.0f));
}

TEST(RasterPoints, UnrequestedChannelsStayEmptyAndNeedNoArrays) {
  const Camera camera = windowCamera(16, 16);
  const std::vector<glm::vec3> positions = {{8.5f, 8.5f, -0.5f}};
  PointSet set;
  set.positions = positions;  // no colours, no normals: the ids channel needs neither
  for (const ChannelMask channels : {ChannelMask(0), ChannelMask(kChannelIds), ChannelMask(kChannelPosition)}) {
    Framebuffer framebuffer = makeFramebuffer(16, 16, channels);
    drawPoints(framebuffer, camera, std::span(&set, 1));
    EXPECT_TRUE(framebuffer.covered(pixelIndex(framebuffer, 8, 8)));
    EXPECT_TRUE(framebuffer.color.empty());
    EXPECT_TRUE(framebuffer.normal.empty());
    EXPECT_EQ(framebuffer.ids.empty(), channels != kChannelIds);
    EXPECT_EQ(framebuffer.position.empty(), channels != kChannelPosition);
  }
}

TEST(RasterPoints, EmptySetsDrawNothing) {
  const Camera camera = windowCamera(16, 16);
  Framebuffer framebuffer = allChannels(16, 16);
  const std::vector<PointSet> sets(3);
  drawPoints(framebuffer, camera, sets);
  drawPoints(framebuffer, camera, {});
  EXPECT_TRUE(coveredPixels(framebuffer).empty());
}

TEST(RasterPoints, MissingArraysAndMismatchedSizesAreRejected) {
  const Camera camera = windowCamera(16, 16);
  const std::vector<glm::vec3> positions(2, glm::vec3(8.5f, 8.5f, -0.5f));
  const std::vector<float> oneFactor = {1.0f};
  PointSet set;
  set.positions = positions;
  Framebuffer colour = makeFramebuffer(16, 16, kChannelColor);
  EXPECT_THROW(drawPoints(colour, camera, std::span(&set, 1)), std::invalid_argument);
  Framebuffer normal = makeFramebuffer(16, 16, kChannelNormal);
  EXPECT_THROW(drawPoints(normal, camera, std::span(&set, 1)), std::invalid_argument);
  set.sizeFactors = oneFactor;
  Framebuffer depth = makeFramebuffer(16, 16, 0);
  EXPECT_THROW(drawPoints(depth, camera, std::span(&set, 1)), std::invalid_argument);
  set.sizeFactors = {};
  Framebuffer wrongSize = makeFramebuffer(8, 16, 0);
  EXPECT_THROW(drawPoints(wrongSize, camera, std::span(&set, 1)), std::invalid_argument);
  EXPECT_TRUE(coveredPixels(colour).empty());
}

}  // namespace
}  // namespace pbs
