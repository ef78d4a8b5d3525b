// upscaleBilinear: what a budget's lower resolution is brought up to the frame's size with. Pixel centres map
// onto each other, colours are interpolated premultiplied (an edge's colour does not darken toward the empty
// pixels beside it, its alpha ramps), the 8-bit variant is the float one rounded, and sizes are checked.
#include <pbs/raster/headlight_shading.hpp>
#include <pbs/raster/image_upscale.hpp>
#include <pbs/raster/seeded_random.hpp>
#include <pbs/raster/thread_arena.hpp>

#include <gtest/gtest.h>

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

TEST(ImageUpscale, TheBytesAreTheFloatImageRoundedForAnyThreadCount) {
  SeededRandom random(7);
  std::vector<glm::vec4> image(17 * 9);
  for (glm::vec4& pixel : image) {
    const float alpha = random.unit() < 0.3 ? 0.0f : float(random.unit());
    pixel = alpha > 0.0f ? glm::vec4(float(random.unit()), float(random.unit()), float(random.unit()), alpha)
                         : glm::vec4(0.0f);
  }
  const std::vector<std::uint8_t> expected = toRgba8(upscaleBilinear(image, 17, 9, 40, 21));
  for (int threads : {1, 2, 4}) {
    std::vector<std::uint8_t> bytes;
    runWithThreads(threads, [&] { bytes = upscaleBilinearRgba8(image, 17, 9, 40, 21); });
    EXPECT_EQ(bytes, expected) << threads << " threads";
  }
}

TEST(ImageUpscale, SizesThatDoNotMatchAreRefused) {
  const std::vector<glm::vec4> image(6, glm::vec4(1.0f));
  EXPECT_THROW(upscaleBilinear(image, 3, 3, 6, 6), std::invalid_argument);
  EXPECT_THROW(upscaleBilinear(image, 3, 2, 0, 6), std::invalid_argument);
  EXPECT_THROW(upscaleBilinearRgba8({}, 0, 0, 6, 6), std::invalid_argument);
}

}  // namespace
}  // namespace pbs
