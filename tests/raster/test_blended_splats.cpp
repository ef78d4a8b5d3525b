// Tests of drawBlendedSplats: coverage conserved at any size, closed interiors, depth against geometry both
// ways, back faces, layers, determinism and bad input.
#include "pbs/raster/blended_splats.hpp"
#include "pbs/raster/thread_arena.hpp"

#include "test_fixtures.hpp"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace pbs {
namespace {

// One unit a pixel (world y = window row), eye depth 0 … 1000 mapped to window depth 0 … 1, so that a
// disc radius of a few pixels is a depth tolerance of a few thousandths.
Camera deepCamera(std::uint32_t width, std::uint32_t height) {
  return orthographicCamera(glm::dmat4(1.0), 0.0, width, height, 0.0, 0.0, 1000.0, width, height);
}

constexpr ChannelMask kBlendChannels = kChannelColor | kChannelNormal | kChannelCoverage;

// Surfels on a jittered grid over [x0, x0 + side] × [y0, y0 + side] at eye depth z (window camera: one
// unit a pixel, depth = −z / 1000), facing the eye, each standing for its grid cell.
struct Patch {
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::u8vec4> colors;
  float spacing = 0.0f;

  SurfelSplatSet set() const {
    return SurfelSplatSet{.positions = positions,
                          .normals = normals,
                          .colors = colors,
                          .radius = spacing,
                          .area = spacing * spacing,
                          .nodeId = 7,
                          .instanceId = 3};
  }
};

Patch patch(float x0, float y0, float side, int perSide, float z, glm::u8vec4 color, std::uint32_t seed = 1) {
  Patch p;
  p.spacing = side / float(perSide);
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> jitter(-0.15f, 0.15f);
  for (int j = 0; j < perSide; ++j)
    for (int i = 0; i < perSide; ++i) {
      const float x = x0 + (float(i) + 0.5f + jitter(random)) * p.spacing;
      const float y = y0 + (float(j) + 0.5f + jitter(random)) * p.spacing;
      p.positions.emplace_back(x, y, z);
      p.normals.emplace_back(0.0f, 0.0f, 1.0f);
      p.colors.push_back(color);
    }
  return p;
}

double totalCoverage(const Framebuffer& framebuffer) {
  double sum = 0.0;
  for (float c : framebuffer.coverage) sum += c;
  return sum;
}

float coverageAt(const Framebuffer& framebuffer, int x, int y) {
  return framebuffer.coverage[std::size_t(y) * framebuffer.width + std::size_t(x)];
}

TEST(BlendedSplats, ALargePatchIsClosedInsideAndCoversItsArea) {
  const Camera camera = deepCamera(64, 64);
  Framebuffer framebuffer = makeFramebuffer(64, 64, kBlendChannels);
  const Patch square = patch(12.0f, 12.0f, 40.0f, 20, -500.0f, glm::u8vec4(200, 100, 50, 255));
  const SurfelSplatSet sets[] = {square.set()};
  drawBlendedSplats(framebuffer, camera, sets);
  // Area conserved: the kernels sum to what the surfels stand for.
  EXPECT_NEAR(totalCoverage(framebuffer), 40.0 * 40.0, 0.03 * 1600.0);
  // Closed inside (two spacings from the edge), empty well outside.
  for (int y = 16; y < 48; ++y)
    for (int x = 16; x < 48; ++x) EXPECT_GT(coverageAt(framebuffer, x, y), 0.9f) << x << "," << y;
  for (int x = 0; x < 64; ++x) {
    EXPECT_EQ(coverageAt(framebuffer, x, 2), 0.0f);
    EXPECT_EQ(coverageAt(framebuffer, x, 60), 0.0f);
  }
  const std::size_t centre = 32 * 64 + 32;
  EXPECT_EQ(framebuffer.color[centre], glm::u8vec4(200, 100, 50, 255));
  EXPECT_NEAR(framebuffer.depth[centre], 0.5f, 1e-6f);
  EXPECT_NEAR(framebuffer.normal[centre].z, 1.0f, 1e-6f);
}

TEST(BlendedSplats, SubPixelSurfelsAddTheFractionOfAPixelTheyStandFor) {
  // A patch of a quarter pixel's area, drawn by 100 surfels: it covers a quarter of a pixel in all, not a
  // pixel per surfel.
  const Camera camera = deepCamera(16, 16);
  Framebuffer framebuffer = makeFramebuffer(16, 16, kBlendChannels);
  const Patch tiny = patch(7.6f, 7.6f, 0.5f, 10, -500.0f, glm::u8vec4(10, 20, 30, 255));
  const SurfelSplatSet sets[] = {tiny.set()};
  drawBlendedSplats(framebuffer, camera, sets);
  EXPECT_NEAR(totalCoverage(framebuffer), 0.25, 0.01);
  int touched = 0;
  for (std::size_t p = 0; p < framebuffer.pixelCount(); ++p)
    if (framebuffer.coverage[p] > 0.0f) {
      ++touched;
      EXPECT_EQ(framebuffer.color[p], glm::u8vec4(10, 20, 30, 255));
    }
  EXPECT_GE(touched, 1);
  EXPECT_LE(touched, 4);
}

// Geometry drawn before: a wall at window depth `depth` over the whole frame.
void fillGeometry(Framebuffer& framebuffer, float depth, glm::u8vec4 color) {
  std::fill(framebuffer.depth.begin(), framebuffer.depth.end(), depth);
  std::fill(framebuffer.color.begin(), framebuffer.color.end(), color);
  std::fill(framebuffer.normal.begin(), framebuffer.normal.end(), glm::vec3(0.0f, 0.0f, 1.0f));
}

TEST(BlendedSplats, GeometryHidesSplatsBehindItAndSplatsInFrontCoverIt) {
  const Camera camera = deepCamera(32, 32);
  const Patch square = patch(4.0f, 4.0f, 24.0f, 12, -500.0f, glm::u8vec4(255, 0, 0, 255));
  const SurfelSplatSet sets[] = {square.set()};
  const glm::u8vec4 wall(0, 0, 255, 255);
  const std::size_t centre = 16 * 32 + 16;

  Framebuffer behind = makeFramebuffer(32, 32, kBlendChannels);
  fillGeometry(behind, 0.25f, wall);  // the wall is nearer than the splats (depth 0.5)
  drawBlendedSplats(behind, camera, sets);
  EXPECT_EQ(behind.color[centre], wall);
  EXPECT_EQ(behind.depth[centre], 0.25f);
  EXPECT_EQ(behind.coverage[centre], 1.0f);

  Framebuffer front = makeFramebuffer(32, 32, kBlendChannels);
  fillGeometry(front, 0.75f, wall);
  drawBlendedSplats(front, camera, sets);
  EXPECT_EQ(front.color[centre], glm::u8vec4(255, 0, 0, 255));
  EXPECT_NEAR(front.depth[centre], 0.5f, 1e-6f);
  EXPECT_EQ(front.coverage[centre], 1.0f);
  // Every pixel is covered (by the wall at least), so coverage is 1 everywhere, and at the patch's soft
  // rim the colour lies between the two.
  for (float c : front.coverage) EXPECT_EQ(c, 1.0f);
  const bool blendedRim =
      std::any_of(front.color.begin(), front.color.end(), [](glm::u8vec4 c) { return c.r > 0 && c.b > 0; });
  EXPECT_TRUE(blendedRim);
}

// A triangle's vertex normals may point inside (shading reads |n · eye|), and a node in its transition band
// draws splats of partial coverage over its own geometry: the two normals, one the other's opposite up to a
// tilt, must blend to the surface's direction, not cancel to a sideways one (dark dots on horse.glb).
TEST(BlendedSplats, PartialSplatsOverGeometryNormalsFacingAwayKeepTheSurfacesFacing) {
  const Camera camera = deepCamera(32, 32);
  Framebuffer framebuffer = makeFramebuffer(32, 32, kBlendChannels);
  fillGeometry(framebuffer, 0.5f, glm::u8vec4(128, 128, 128, 255));
  const glm::vec3 inward = -glm::normalize(glm::vec3(0.3f, 0.0f, 1.0f));  // facing the eye at 0.96, negated
  std::fill(framebuffer.normal.begin(), framebuffer.normal.end(), inward);
  const Patch square = patch(0.0f, 0.0f, 32.0f, 16, -500.0f, glm::u8vec4(128, 128, 128, 255));
  SurfelSplatSet half = square.set();
  half.area *= 0.5f;  // about half a pixel's coverage everywhere: the band's middle
  const SurfelSplatSet sets[] = {half};
  drawBlendedSplats(framebuffer, camera, sets);
  int blended = 0;
  for (int y = 8; y < 24; ++y)
    for (int x = 8; x < 24; ++x) {
      const glm::vec3 n = framebuffer.normal[std::size_t(y) * 32 + std::size_t(x)];
      EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f) << x << "," << y;
      EXPECT_GT(std::abs(n.z), 0.95f) << x << "," << y << ": " << n.x << " " << n.y << " " << n.z;
      blended += n != inward && n != -inward && n != glm::vec3(0.0f, 0.0f, 1.0f);
    }
  EXPECT_GT(blended, 200);  // the splats did blend with the geometry, not replace or miss it
}

TEST(BlendedSplats, TheFrontSurfaceWinsOverOneBehindIt) {
  const Camera camera = deepCamera(32, 32);
  Framebuffer framebuffer = makeFramebuffer(32, 32, kBlendChannels);
  const Patch near = patch(4.0f, 4.0f, 24.0f, 12, -300.0f, glm::u8vec4(0, 255, 0, 255));
  const Patch far = patch(4.0f, 4.0f, 24.0f, 12, -700.0f, glm::u8vec4(255, 0, 0, 255), 2);
  // Drawn far first: order must not matter.
  const SurfelSplatSet sets[] = {far.set(), near.set()};
  drawBlendedSplats(framebuffer, camera, sets);
  EXPECT_EQ(framebuffer.color[16 * 32 + 16], glm::u8vec4(0, 255, 0, 255));
  EXPECT_NEAR(framebuffer.depth[16 * 32 + 16], 0.3f, 1e-6f);
}

TEST(BlendedSplats, SurfelsFacingAwayAreNotDrawnUnlessCullingIsOff) {
  const Camera camera = deepCamera(32, 32);
  Patch away = patch(4.0f, 4.0f, 24.0f, 12, -500.0f, glm::u8vec4(255, 255, 255, 255));
  for (glm::vec3& n : away.normals) n = glm::vec3(0.0f, 0.0f, -1.0f);
  SurfelSplatSet sets[] = {away.set()};
  Framebuffer culled = makeFramebuffer(32, 32, kBlendChannels);
  drawBlendedSplats(culled, camera, sets);
  EXPECT_EQ(totalCoverage(culled), 0.0);
  Framebuffer all = makeFramebuffer(32, 32, kBlendChannels);
  sets[0].backFaceCosine = -1.0f;
  drawBlendedSplats(all, camera, sets);
  EXPECT_NEAR(totalCoverage(all), 24.0 * 24.0, 0.05 * 576.0);
  // Drawn from behind, the normal written faces the eye.
  EXPECT_NEAR(all.normal[16 * 32 + 16].z, 1.0f, 1e-6f);
}

TEST(BlendedSplats, AnEdgeOnPatchCoversAlmostNothing) {
  // Seen edge-on a disc projects to a line: it covers what its sliver of area covers, not its radius².
  const Camera camera = deepCamera(32, 32);
  Patch edgeOn = patch(4.0f, 4.0f, 24.0f, 12, -500.0f, glm::u8vec4(255, 255, 255, 255));
  for (glm::vec3& n : edgeOn.normals) n = glm::vec3(1.0f, 0.0f, 0.0f);
  SurfelSplatSet sets[] = {edgeOn.set()};
  sets[0].backFaceCosine = -1.0f;
  Framebuffer framebuffer = makeFramebuffer(32, 32, kBlendChannels);
  drawBlendedSplats(framebuffer, camera, sets);
  EXPECT_LT(totalCoverage(framebuffer), 1.0);
}

TEST(BlendedSplats, BitIdenticalForAnyThreadCount) {
  const Camera camera = deepCamera(200, 120);
  std::vector<Patch> patches;
  for (int i = 0; i < 12; ++i)
    patches.push_back(patch(float(i * 13 % 170), float(i * 29 % 90), 30.0f, 40, -100.0f - 70.0f * float(i),
                            glm::u8vec4(20 * i, 255 - 20 * i, 90, 255), std::uint32_t(i + 1)));
  std::vector<SurfelSplatSet> sets;
  for (const Patch& p : patches) sets.push_back(p.set());
  std::vector<Framebuffer> images;
  for (const int threads : {1, 2, 5}) {
    images.push_back(makeFramebuffer(200, 120, kBlendChannels | kChannelIds));
    runWithThreads(threads, [&] { drawBlendedSplats(images.back(), camera, sets); });
  }
  for (std::size_t i = 1; i < images.size(); ++i) {
    EXPECT_EQ(images[i].depth, images[0].depth);
    EXPECT_EQ(images[i].color, images[0].color);
    EXPECT_EQ(images[i].normal, images[0].normal);
    EXPECT_EQ(images[i].coverage, images[0].coverage);
    EXPECT_EQ(images[i].ids, images[0].ids);
  }
  EXPECT_GT(totalCoverage(images[0]), 1000.0);
}

// Footprints are projected in batches, a step at a time across each batch's surfels (blend_footprint.cpp): what a
// surfel draws must not depend on which surfels share its batch, nor on how many do. Surfels of every kind (facing
// either way, no normal, not finite, behind the eye, off screen, edge-on) drawn as one set and as sets of other
// lengths give the same image, in perspective and orthographic views.
TEST(BlendedSplats, ASurfelDrawsTheSameWhateverSurfelsShareItsBatch) {
  std::mt19937 random(11);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::u8vec4> colors;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int i = 0; i < 700; ++i) {
    glm::vec3 p(12.0f * unit(random), 8.0f * unit(random), 10.0f * unit(random));
    glm::vec3 n(unit(random), unit(random), unit(random));
    if (i % 97 == 5) p.x = nan;
    if (i % 89 == 7) n = glm::vec3(0.0f);
    if (i % 83 == 9) p.z = 60.0f;                       // behind the perspective eye
    if (i % 79 == 11) p.x = 400.0f;                     // off screen
    if (i % 73 == 13) n = glm::vec3(1.0f, 0.0f, 0.0f);  // edge-on to the orthographic view
    positions.push_back(p);
    normals.push_back(n);
    colors.emplace_back(std::uint8_t(i), std::uint8_t(i * 7), std::uint8_t(i * 13), 255);
  }
  const auto setOf = [&](std::size_t first, std::size_t count) {
    return SurfelSplatSet{.positions = std::span(positions).subspan(first, count),
                          .normals = std::span(normals).subspan(first, count),
                          .colors = std::span(colors).subspan(first, count),
                          .worldFromObject = glm::translate(glm::dmat4(1.0), glm::dvec3(0.5, -0.25, 0.0)),
                          .radius = 0.6f,
                          .area = 0.36f};
  };
  const auto draw = [&](const Camera& camera, std::span<const std::size_t> lengths) {
    std::vector<SurfelSplatSet> sets;
    for (std::size_t first = 0, s = 0; first < positions.size(); ++s) {
      const std::size_t count = std::min(lengths[s % lengths.size()], positions.size() - first);
      sets.push_back(setOf(first, count));
      first += count;
    }
    Framebuffer image = makeFramebuffer(camera.width, camera.height, kBlendChannels);
    drawBlendedSplats(image, camera, sets);
    return image;
  };
  const std::size_t whole[] = {positions.size()}, singles[] = {1}, mixed[] = {37, 64, 65, 1, 129, 3, 200};
  const Camera cameras[] = {
      perspectiveCamera(glm::lookAt(glm::dvec3(3.0, 4.0, 40.0), glm::dvec3(0.0), glm::dvec3(0.0, 1.0, 0.0)), 0.8, 0.5,
                        200.0, 160, 120),
      orthographicCamera(glm::lookAt(glm::dvec3(-50.0, 0.0, 0.0), glm::dvec3(0.0), glm::dvec3(0.0, 1.0, 0.0)), -14.0,
                         14.0, -10.0, 10.0, 1.0, 100.0, 140, 100)};
  for (const Camera& camera : cameras) {
    const Framebuffer reference = draw(camera, whole);
    EXPECT_GT(totalCoverage(reference), 500.0);
    for (const std::span<const std::size_t> lengths :
         {std::span<const std::size_t>(singles), std::span<const std::size_t>(mixed)}) {
      const Framebuffer image = draw(camera, lengths);
      EXPECT_EQ(image.depth, reference.depth);
      EXPECT_EQ(image.color, reference.color);
      EXPECT_EQ(image.normal, reference.normal);
      EXPECT_EQ(image.coverage, reference.coverage);
    }
  }
}

TEST(BlendedSplats, StiffInputsAreDroppedOrDefined) {
  const Camera camera = deepCamera(16, 16);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<glm::vec3> positions = {{nan, 8.0f, -500.0f}, {8.0f, 8.0f, -5000.0f}, {8.0f, 8.0f, -500.0f}};
  const std::vector<glm::vec3> normals = {{0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 0.0f}};
  const std::vector<glm::u8vec4> colors(3, glm::u8vec4(9, 9, 9, 255));
  // NaN and out-of-range depth dropped; a zero normal faces the eye.
  SurfelSplatSet set{.positions = positions, .normals = normals, .colors = colors, .radius = 2.0f, .area = 4.0f};
  Framebuffer framebuffer = makeFramebuffer(16, 16, kBlendChannels);
  drawBlendedSplats(framebuffer, camera, std::span(&set, 1));
  // One disc alone: its area, plus what the rise above S = ½ adds at its rim.
  EXPECT_GE(totalCoverage(framebuffer), 4.0);
  EXPECT_LE(totalCoverage(framebuffer), 5.5);
  // No radius: nothing.
  set.radius = 0.0f;
  Framebuffer none = makeFramebuffer(16, 16, kBlendChannels);
  drawBlendedSplats(none, camera, std::span(&set, 1));
  EXPECT_EQ(totalCoverage(none), 0.0);
}

TEST(BlendedSplats, BadInputThrows) {
  const Camera camera = deepCamera(8, 8);
  const Patch p = patch(1.0f, 1.0f, 4.0f, 4, -500.0f, glm::u8vec4(1, 2, 3, 255));
  const SurfelSplatSet sets[] = {p.set()};
  Framebuffer noCoverage = makeFramebuffer(8, 8, kChannelColor | kChannelNormal);
  EXPECT_THROW(drawBlendedSplats(noCoverage, camera, sets), std::invalid_argument);
  Framebuffer positions = makeFramebuffer(8, 8, kBlendChannels | kChannelPosition);
  EXPECT_THROW(drawBlendedSplats(positions, camera, sets), std::invalid_argument);
  Framebuffer wrongSize = makeFramebuffer(9, 8, kBlendChannels);
  EXPECT_THROW(drawBlendedSplats(wrongSize, camera, sets), std::invalid_argument);
  SurfelSplatSet short_ = p.set();
  short_.colors = short_.colors.first(2);
  Framebuffer framebuffer = makeFramebuffer(8, 8, kBlendChannels);
  EXPECT_THROW(drawBlendedSplats(framebuffer, camera, std::span(&short_, 1)), std::invalid_argument);
}

}  // namespace
}  // namespace pbs
