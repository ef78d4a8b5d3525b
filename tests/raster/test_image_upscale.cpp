// upscaleBilinear: what a budget's lower resolution is brought up to the frame's size with. Pixel centres map
// onto each other, colours are interpolated premultiplied (an edge's colour does not darken toward the empty
// pixels beside it, its alpha ramps), the 8-bit variant is the float one rounded, and sizes are checked.
#include <pbs/raster/headlight_shading.hpp>
#include <pbs/raster/image_upscale.hpp>
#include <pbs/raster/seeded_random.hpp>
#include <pbs/raster/thread_arena.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace pbs {
namespace {

TEST(ImageUpscale, AConstantImageStaysConstantAndTheSizeIsTheOneAskedFor) {
  const glm::vec4 grey(0.25f, 0.5f, 0.75f, 1.0f);
  const std::vector<glm::vec4> image(3 * 2, grey);
  const std::vector<glm::vec4> up = upscaleBilinear(image, 3, 2, 8, 5);
  ASSERT_EQ(up.size(), 8u * 5u);
  for (const glm::vec4& pixel : up) EXPECT_EQ(pixel, grey);
}

// Two pixels, red and empty, doubled: the outer output pixels clamp to their input pixel, the inner ones lie a
// quarter and three quarters of the way across, so their alpha is ¾ and ¼ and their colour stays red.
TEST(ImageUpscale, AnEdgeRampsInAlphaWithoutDarkening) {
  const std::vector<glm::vec4> image{{1.0f, 0.0f, 0.0f, 1.0f}, glm::vec4(0.0f)};
  const std::vector<glm::vec4> up = upscaleBilinear(image, 2, 1, 4, 1);
  ASSERT_EQ(up.size(), 4u);
  EXPECT_EQ(up[0], glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
  EXPECT_EQ(up[1], glm::vec4(1.0f, 0.0f, 0.0f, 0.75f));
  EXPECT_EQ(up[2], glm::vec4(1.0f, 0.0f, 0.0f, 0.25f));
  EXPECT_EQ(up[3], glm::vec4(0.0f));
}

// A linear ramp stays linear between the first and last pixel centres, at 3× (the budget's divisor 3).
TEST(ImageUpscale, ALinearRampIsInterpolatedExactlyBetweenPixelCentres) {
  std::vector<glm::vec4> image;
  for (int x = 0; x < 4; ++x) image.push_back({float(x) / 4.0f, 0.5f, 0.5f, 1.0f});
  const std::vector<glm::vec4> up = upscaleBilinear(image, 4, 1, 12, 1);
  // Output pixel i's centre lies at input coordinate (i + 0.5) / 3 − 0.5.
  for (int i = 1; i < 11; ++i) {
    const float at = (float(i) + 0.5f) / 3.0f - 0.5f;
    EXPECT_NEAR(up[std::size_t(i)].r, at / 4.0f, 1e-6f) << i;
  }
}

// Straight colours, a third of the pixels empty.
std::vector<glm::vec4> randomImage(std::size_t pixels, std::uint64_t seed) {
  SeededRandom random(seed);
  std::vector<glm::vec4> image(pixels);
  for (glm::vec4& pixel : image) {
    const float alpha = random.unit() < 0.3 ? 0.0f : float(random.unit());
    pixel = alpha > 0.0f ? glm::vec4(float(random.unit()), float(random.unit()), float(random.unit()), alpha)
                         : glm::vec4(0.0f);
  }
  return image;
}

// Each output pixel against the formula evaluated on its own in double precision: premultiply the four input
// pixels around its centre, weigh them bilinearly, divide by the alpha. Odd sizes, so that rows end in a lone
// pixel, and ratios that are not whole.
TEST(ImageUpscale, EveryPixelIsTheBilinearFormula) {
  const std::uint32_t w = 7, h = 5, toW = 23, toH = 12;
  const std::vector<glm::vec4> image = randomImage(w * h, 11);
  const std::vector<glm::vec4> up = upscaleBilinear(image, w, h, toW, toH);
  ASSERT_EQ(up.size(), std::size_t(toW) * toH);
  const auto premultiplied = [&](std::uint32_t x, std::uint32_t y) {
    const glm::dvec4 c(image[std::size_t(y) * w + x]);
    return glm::dvec4(glm::dvec3(c) * c.a, c.a);
  };
  for (std::uint32_t y = 0; y < toH; ++y) {
    for (std::uint32_t x = 0; x < toW; ++x) {
      const double at[2] = {std::clamp((x + 0.5) * w / toW - 0.5, 0.0, w - 1.0),
                            std::clamp((y + 0.5) * h / toH - 0.5, 0.0, h - 1.0)};
      const auto x0 = std::uint32_t(at[0]), y0 = std::uint32_t(at[1]);
      const std::uint32_t x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
      const double tx = at[0] - x0, ty = at[1] - y0;
      const glm::dvec4 c = (premultiplied(x0, y0) * (1 - tx) + premultiplied(x1, y0) * tx) * (1 - ty) +
                           (premultiplied(x0, y1) * (1 - tx) + premultiplied(x1, y1) * tx) * ty;
      const glm::dvec4 expected = c.a > 1e-6 ? glm::dvec4(glm::dvec3(c) / c.a, c.a) : glm::dvec4(0.0);
      const glm::vec4 got = up[std::size_t(y) * toW + x];
      // Colours divided by a tiny alpha amplify float rounding: compare them where alpha is not tiny.
      EXPECT_NEAR(got.a, expected.a, 1e-6) << x << "," << y;
      if (c.a > 1e-3) {
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], expected[k], 1e-4) << x << "," << y << " channel " << k;
      }
    }
  }
}

TEST(ImageUpscale, TheBytesAreTheFloatImageRoundedForAnyThreadCount) {
  const std::vector<glm::vec4> image = randomImage(17 * 9, 7);
  for (std::uint32_t toWidth : {40u, 41u}) {
    const std::vector<std::uint8_t> expected = toRgba8(upscaleBilinear(image, 17, 9, toWidth, 21));
    for (int threads : {1, 2, 4}) {
      std::vector<std::uint8_t> bytes;
      runWithThreads(threads, [&] { bytes = upscaleBilinearRgba8(image, 17, 9, toWidth, 21); });
      EXPECT_EQ(bytes, expected) << toWidth << " wide, " << threads << " threads";
    }
  }
}

// Rows made as they are read (written into the scratch row) give the same pixels as the image held whole.
TEST(ImageUpscale, RowsMadeOnDemandUpscaleAsTheWholeImage) {
  const std::uint32_t w = 17, h = 9, toW = 41, toH = 27;
  const std::vector<glm::vec4> image = randomImage(w * h, 5);
  const UpscaleRows rows = [&](std::uint32_t y, glm::vec4* scratch) {
    std::copy_n(image.begin() + std::ptrdiff_t(y) * w, w, scratch);
    return scratch;
  };
  for (int threads : {1, 3}) {
    runWithThreads(threads, [&] {
      EXPECT_EQ(upscaleBilinear(rows, w, h, toW, toH), upscaleBilinear(image, w, h, toW, toH)) << threads;
      EXPECT_EQ(upscaleBilinearRgba8(rows, w, h, toW, toH), upscaleBilinearRgba8(image, w, h, toW, toH)) << threads;
    });
  }
}

TEST(ImageUpscale, SizesThatDoNotMatchAreRefused) {
  const std::vector<glm::vec4> image(6, glm::vec4(1.0f));
  EXPECT_THROW(upscaleBilinear(image, 3, 3, 6, 6), std::invalid_argument);
  EXPECT_THROW(upscaleBilinear(image, 3, 2, 0, 6), std::invalid_argument);
  EXPECT_THROW(upscaleBilinearRgba8(std::span<const glm::vec4>{}, 0, 0, 6, 6), std::invalid_argument);
}

}  // namespace
}  // namespace pbs
