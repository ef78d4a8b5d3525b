// Supersampling in both exact renderers: the fixed sample pattern, the shifted cameras, the resolve,
// bit-identical frames for any thread count, and the rasterizer and the rays converging to one image.
#include "test_fixtures.hpp"

#include <pbs/raster/headlight_shading.hpp>
#include <pbs/raster/image_metrics.hpp>
#include <pbs/raster/orbit_camera.hpp>
#include <pbs/raster/supersampling.hpp>
#include <pbs/raster/thread_arena.hpp>
#include <pbs/surfels/frame_renderer.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <stdexcept>
#include <vector>

namespace pbs::test {
namespace {

TEST(SamplePattern, IsARotatedGridWithOneSampleInEveryRowAndColumn) {
  ASSERT_EQ(subpixelSamples(1).size(), 1u);
  EXPECT_EQ(subpixelSamples(1)[0], glm::dvec2(0.5, 0.5));
  for (std::uint32_t n : {4u, 16u, 64u, 256u}) {
    const std::vector<glm::dvec2> samples = subpixelSamples(n);
    ASSERT_EQ(samples.size(), n);
    std::set<int> columns, rows;
    for (const glm::dvec2& s : samples) {
      ASSERT_GE(s.x, 0.0);
      ASSERT_LT(s.x, 1.0);
      ASSERT_GE(s.y, 0.0);
      ASSERT_LT(s.y, 1.0);
      columns.insert(int(std::floor(s.x * n)));
      rows.insert(int(std::floor(s.y * n)));
    }
    EXPECT_EQ(columns.size(), n) << "n-rooks: every one of the n columns holds a sample";
    EXPECT_EQ(rows.size(), n) << "and every row";
    // The mean position is the pixel centre, so the box filter is not biased to one side.
    glm::dvec2 mean(0.0);
    for (const glm::dvec2& s : samples) mean += s / double(n);
    EXPECT_NEAR(mean.x, 0.5, 1e-12);
    EXPECT_NEAR(mean.y, 0.5, 1e-12);
  }
  // The classic 4-sample rotated grid.
  const std::vector<glm::dvec2> four = subpixelSamples(4);
  EXPECT_EQ(four[0], glm::dvec2(0.125, 0.375));
  EXPECT_EQ(four[1], glm::dvec2(0.375, 0.875));
  EXPECT_EQ(four[2], glm::dvec2(0.625, 0.125));
  EXPECT_EQ(four[3], glm::dvec2(0.875, 0.625));
  for (std::uint32_t bad : {0u, 2u, 8u, 15u, 1024u}) {
    EXPECT_FALSE(isSupportedSampleCount(bad)) << bad;
    EXPECT_THROW(subpixelSamples(bad), std::invalid_argument) << bad;
  }
}

TEST(SamplePattern, ShiftedCamerasSampleTheirPositionExactly) {
  const Camera camera = orbitCamera(glm::dvec3(1.0, 2.0, 3.0), 4.0, Orbit{}, 320, 200);
  const glm::dvec4 clip = camera.clipFromWorld() * glm::dvec4(1.5, 2.5, 2.0, 1.0);
  const glm::dvec3 window = windowFromClip(camera, clip);
  EXPECT_EQ(subpixelCamera(camera, glm::dvec2(0.5), 1).projection, camera.projection) << "the centre is no shift";
  EXPECT_EQ(subpixelCamera(camera, glm::dvec2(0.5), 1).sampleSpacing, 1.0);
  for (const glm::dvec2& sample : subpixelSamples(16)) {
    const Camera shifted = subpixelCamera(camera, sample, 16);
    EXPECT_EQ(shifted.view, camera.view);
    EXPECT_EQ(shifted.sampleSpacing, 0.25) << "16 samples a pixel lie a quarter pixel apart";
    const glm::dvec3 moved = windowFromClip(shifted, shifted.clipFromWorld() * glm::dvec4(1.5, 2.5, 2.0, 1.0));
    // The shifted camera's pixel centre (px + 0.5) is the original's px + sample: points move by −(sample − 0.5).
    EXPECT_NEAR(moved.x, window.x - (sample.x - 0.5), 1e-9);
    EXPECT_NEAR(moved.y, window.y - (sample.y - 0.5), 1e-9);
    EXPECT_NEAR(moved.z, window.z, 1e-12) << "depth is not moved";
  }
}

TEST(SampleResolve, BoxFilterGivesStraightColourAndCoverage) {
  SampleSums sums{std::vector<glm::vec4>(3, glm::vec4(0.0f)), 4};
  sums.sums[0] = glm::vec4(0.4f, 0.8f, 1.2f, 2.0f);  // two of four samples hit, colours summing to these
  sums.sums[1] = glm::vec4(2.0f, 2.0f, 2.0f, 4.0f);  // all four
  const std::vector<glm::vec4> image = resolveSamples(sums);
  EXPECT_EQ(image[0], glm::vec4(0.2f, 0.4f, 0.6f, 0.5f));
  EXPECT_EQ(image[1], glm::vec4(0.5f, 0.5f, 0.5f, 1.0f));
  EXPECT_EQ(image[2], glm::vec4(0.0f)) << "no sample hit: background";
  EXPECT_THROW(resolveSamples(SampleSums{}), std::invalid_argument);
}

// The two groups of boxes seen from an orbit, small enough on screen that edges cover many pixels' worth.
struct GroupsView {
  Scene scene = twoIdenticalGroups();
  Hierarchy hierarchy = analyzeHierarchy(scene);
  Camera camera;
  GroupsView() {
    Bounds bounds;
    for (std::uint32_t root : scene.roots) bounds.extend(hierarchy.worldBounds[root]);
    camera = orbitCamera(bounds.center(), 0.5 * glm::length(bounds.size()), Orbit{35.0, 25.0, 2.2}, 160, 120);
  }
  RgbaImage render(RenderMode mode, std::uint32_t samples) const {
    FrameRenderer renderer(scene, hierarchy, {.mode = mode, .samples = samples}, camera.width, camera.height);
    return RgbaImage{camera.width, camera.height, renderer.render(camera).image};
  }
};

bool sameBits(const RgbaImage& a, const RgbaImage& b) {
  return a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(glm::vec4)) == 0;
}

TEST(Supersampling, FramesAreBitIdenticalForAnyThreadCount) {
  const GroupsView view;
  for (RenderMode mode : {RenderMode::Exact, RenderMode::Embree}) {
    RgbaImage one, two, many;
    runWithThreads(1, [&] { one = view.render(mode, 16); });
    runWithThreads(2, [&] { two = view.render(mode, 16); });
    runWithThreads(0, [&] { many = view.render(mode, 16); });
    EXPECT_TRUE(sameBits(one, two)) << renderModeName(mode);
    EXPECT_TRUE(sameBits(one, many)) << renderModeName(mode);
    // Edges are covered in part: fractional alpha exists, colour stays in range.
    std::size_t partial = 0;
    for (const glm::vec4& p : one.pixels) {
      partial += p.a > 0.0f && p.a < 1.0f;
      EXPECT_TRUE(p.a >= 0.0f && p.a <= 1.0f && p.r >= 0.0f && p.r <= 1.0f);
    }
    EXPECT_GT(partial, 100u) << renderModeName(mode);
  }
}

// A renderer clears only depth between passes (Embree: nothing), leaving the last view's colour and
// normal in its G-buffer: the next view must not show them. Reused from a near view (which covers
// most pixels) to a far one (which covers few), each frame is bit for bit a fresh renderer's.
TEST(Supersampling, AReusedRendererLeavesNothingOfTheLastView) {
  const GroupsView view;
  Camera near = view.camera, far = view.camera;
  Bounds bounds;
  for (std::uint32_t root : view.scene.roots) bounds.extend(view.hierarchy.worldBounds[root]);
  near = orbitCamera(bounds.center(), 0.5 * glm::length(bounds.size()), Orbit{10.0, 40.0, 0.9}, 160, 120);
  far = orbitCamera(bounds.center(), 0.5 * glm::length(bounds.size()), Orbit{200.0, 15.0, 6.0}, 160, 120);
  for (RenderMode mode : {RenderMode::Exact, RenderMode::Embree}) {
    for (std::uint32_t samples : {1u, 4u}) {
      FrameRenderer reused(view.scene, view.hierarchy, {.mode = mode, .samples = samples}, 160, 120);
      EXPECT_EQ(reused.channels(), ChannelMask{kChannelColor | kChannelNormal}) << "no position, ids or coverage";
      EXPECT_EQ(reused.clearsDepth(), mode != RenderMode::Embree);
      const RgbaImage first{160, 120, reused.render(near).image};
      const RgbaImage second{160, 120, reused.render(far).image};
      FrameRenderer fresh(view.scene, view.hierarchy, {.mode = mode, .samples = samples}, 160, 120);
      const RgbaImage expected{160, 120, fresh.render(far).image};
      EXPECT_TRUE(sameBits(second, expected)) << renderModeName(mode) << " " << samples;
      std::size_t nearCovered = 0, farCovered = 0;
      for (std::size_t i = 0; i < first.pixels.size(); ++i) {
        nearCovered += first.pixels[i].a > 0.0f;
        farCovered += second.pixels[i].a > 0.0f;
      }
      EXPECT_GT(nearCovered, 4 * farCovered) << "the near view must cover pixels the far one leaves empty";
    }
  }
}

// A frame bound for an 8-bit file is shaded straight to bytes, the same bytes the float image converts to;
// one made for no file is shaded not at all, and draws and counts the same.
TEST(Supersampling, EightBitAndNoImageFramesAreTheFloatFramesBytesAndCounts) {
  const GroupsView view;
  for (RenderMode mode : {RenderMode::Exact, RenderMode::Embree}) {
    for (std::uint32_t samples : {1u, 4u}) {
      FrameRenderer floats(view.scene, view.hierarchy, {.mode = mode, .samples = samples}, 160, 120);
      FrameRenderer bytes(view.scene, view.hierarchy, {.mode = mode, .samples = samples, .image = FrameImage::Rgba8},
                          160, 120);
      FrameRenderer none(view.scene, view.hierarchy, {.mode = mode, .samples = samples, .image = FrameImage::None}, 160,
                         120);
      const FrameResult expected = floats.render(view.camera);
      const FrameResult eightBit = bytes.render(view.camera);
      const FrameResult nothing = none.render(view.camera);
      EXPECT_TRUE(eightBit.image.empty());
      EXPECT_EQ(eightBit.rgba8, toRgba8(expected.image)) << renderModeName(mode) << " " << samples;
      EXPECT_TRUE(nothing.image.empty() && nothing.rgba8.empty());
      EXPECT_EQ(nothing.stats.triangles, expected.stats.triangles);
    }
  }
}

// toRgba8 rounds each channel to the nearest byte with halves away from zero, clamps to [0, 1], and takes
// NaN as 0.
TEST(Supersampling, BytesRoundLikeLround) {
  std::vector<glm::vec4> image;
  for (int k = 0; k <= 510; ++k) {
    const float half = float(k) / 510.0f;  // every byte and every half between two
    image.emplace_back(half, std::nextafter(half, 0.0f), std::nextafter(half, 1.0f), float(k) / 255.0f);  // to 2
  }
  image.emplace_back(-0.5f, 1.5f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity());
  const std::vector<std::uint8_t> bytes = toRgba8(image);
  for (std::size_t i = 0; i + 1 < image.size(); ++i)
    for (int c = 0; c < 4; ++c)
      ASSERT_EQ(bytes[i * 4 + std::size_t(c)], std::uint8_t(std::lround(std::clamp(image[i][c], 0.0f, 1.0f) * 255.0f)))
          << i << " " << c;
  const std::size_t last = (image.size() - 1) * 4;
  EXPECT_EQ(bytes[last], 0);
  EXPECT_EQ(bytes[last + 1], 255);
  EXPECT_EQ(bytes[last + 2], 0) << "NaN";
  EXPECT_EQ(bytes[last + 3], 255);
  // The one-pixel form (four lanes at once) is the per-channel one, on these and the odd values.
  image.emplace_back(-std::numeric_limits<float>::infinity(), -0.0f, std::numeric_limits<float>::denorm_min(),
                     std::nextafter(1.0f, 2.0f));
  for (const glm::vec4& pixel : image)
    EXPECT_EQ(toRgba8(pixel), glm::u8vec4(toByte(pixel.r), toByte(pixel.g), toByte(pixel.b), toByte(pixel.a)))
        << pixel.r << " " << pixel.g << " " << pixel.b << " " << pixel.a;
}

TEST(Supersampling, OneSampleIsTheUnsupersampledFrame) {
  const GroupsView view;
  for (RenderMode mode : {RenderMode::Exact, RenderMode::Embree}) {
    const RgbaImage image = view.render(mode, 1);
    for (const glm::vec4& p : image.pixels) ASSERT_TRUE(p.a == 0.0f || p.a == 1.0f) << renderModeName(mode);
  }
}

TEST(Supersampling, RasterizerAndRaysConvergeAndSixteenSamplesAreCloseToTheReference) {
  const GroupsView view;
  const RgbaImage reference = view.render(RenderMode::Embree, 64);
  const RgbaImage exact16 = view.render(RenderMode::Exact, 16);
  const RgbaImage embree16 = view.render(RenderMode::Embree, 16);
  const RgbaImage embree1 = view.render(RenderMode::Embree, 1);
  const RgbaImage exact1 = view.render(RenderMode::Exact, 1);

  // The two renderers sample the same positions: at 16 samples they agree to rounding at a few edges.
  const ImageDifference between = compareImages(exact16, embree16);
  EXPECT_LT(between.flipForegroundMean, 0.01);
  EXPECT_GT(between.foregroundPsnr, 40.0);
  EXPECT_NEAR(between.coverageA, between.coverageB, 0.002 * between.coverageB);

  const ImageDifference at16 = compareImages(embree16, reference);
  const ImageDifference at1 = compareImages(embree1, reference);
  const ImageDifference exactAt1 = compareImages(exact1, reference);
  EXPECT_LT(at16.flipForegroundMean * 3.0, at1.flipForegroundMean)
      << "16 samples: " << at16.flipForegroundMean << ", 1 sample: " << at1.flipForegroundMean;
  EXPECT_GT(at16.foregroundPsnr, at1.foregroundPsnr + 6.0);
  EXPECT_NEAR(exactAt1.flipForegroundMean, at1.flipForegroundMean, 0.1 * at1.flipForegroundMean)
      << "both exact renderers at 1 sample are the same picture";
  // Coverage converges too: the 16-sample image neither loses nor adds much of the reference's coverage.
  EXPECT_LT(at16.holeFraction, 0.02);
  EXPECT_LT(at16.bloatFraction, 0.02);
}

// --texture-filter: the frame's cameras' own probes (anisotropic), one probe, or level 0 alone, in both exact
// renderers. The slanted checkerboard's far half is smooth where the texture is filtered (its texels averaged to
// grey), and alternates between dark and light neighbours where level 0 alone is sampled; a frame with a named
// filtering is the frame of a camera that carries it.
TEST(TextureFiltering, NamedFilteringDrawsAsACameraCarryingIt) {
  constexpr std::uint32_t kSize = 96;
  const Scene scene = slantedChecker();
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  const Camera camera = slantedCheckerCamera(kSize);
  const auto render = [&](RenderMode mode, TextureFiltering textures, const Camera& view) {
    FrameRenderer renderer(scene, hierarchy, {.mode = mode, .image = FrameImage::Rgba8, .textures = textures}, kSize,
                           kSize);
    return renderer.render(view).rgba8;
  };
  // The mean red difference between horizontal neighbours, both covered, in the upper (far) half.
  const auto farNeighbourDifference = [&](const std::vector<std::uint8_t>& rgba8) {
    std::size_t pairs = 0, sum = 0;
    for (std::size_t y = 0; y < kSize / 2; ++y)
      for (std::size_t x = 0; x + 1 < kSize; ++x) {
        const std::size_t pixel = y * kSize + x;
        if (rgba8[pixel * 4 + 3] != 255 || rgba8[pixel * 4 + 7] != 255) continue;
        ++pairs;
        sum += std::size_t(std::abs(int(rgba8[pixel * 4]) - int(rgba8[pixel * 4 + 4])));
      }
    EXPECT_GT(pairs, std::size_t(kSize) * 4);
    return double(sum) / double(std::max<std::size_t>(pairs, 1));
  };
  for (RenderMode mode : {RenderMode::Exact, RenderMode::Embree}) {
    Camera isotropic = camera, unfiltered = camera;
    isotropic.textureProbes = 1;
    unfiltered.textureProbes = 0;
    const std::vector<std::uint8_t> anisotropicFrame = render(mode, TextureFiltering::Anisotropic, camera);
    const std::vector<std::uint8_t> isotropicFrame = render(mode, TextureFiltering::Isotropic, camera);
    const std::vector<std::uint8_t> noneFrame = render(mode, TextureFiltering::None, camera);
    EXPECT_TRUE(isotropicFrame == render(mode, TextureFiltering::Anisotropic, isotropic)) << renderModeName(mode);
    EXPECT_TRUE(noneFrame == render(mode, TextureFiltering::Anisotropic, unfiltered)) << renderModeName(mode);
    EXPECT_TRUE(anisotropicFrame != isotropicFrame) << "probes along the slant sample finer levels";
    const double none = farNeighbourDifference(noneFrame), isotropicDifference = farNeighbourDifference(isotropicFrame);
    EXPECT_GT(none, 4.0 * isotropicDifference) << renderModeName(mode) << ": level 0 alone shows single texels";
    EXPECT_GT(none, 4.0 * farNeighbourDifference(anisotropicFrame)) << renderModeName(mode);
    EXPECT_GT(none, 15.0) << renderModeName(mode) << ": about a tenth of the range, shaded at a slant";
  }
  EXPECT_STREQ(textureFilteringName(TextureFiltering::None), "none");
}

}  // namespace
}  // namespace pbs::test
