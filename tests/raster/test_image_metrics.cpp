// Image-difference metrics (composited RMSE and PSNR over the whole image and the foreground, luminance
// SSIM, FLIP, holes and bloat, pass/fail limits) and `pbs compare` over PNG and EXR files.
#include "test_support.hpp"

#include <pbs/raster/flip.hpp>
#include <pbs/raster/image_metrics.hpp>
#include <pbs/raster/thread_arena.hpp>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace pbs::test {
namespace {

// A smooth colour pattern with a little seeded noise, every pixel surface: texture for SSIM to see.
RgbaImage patternImage(std::uint32_t width, std::uint32_t height, std::uint32_t seed = 7) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> noise(-0.05f, 0.05f);
  RgbaImage image{width, height, std::vector<glm::vec4>(std::size_t(width) * height)};
  for (std::uint32_t y = 0; y < height; ++y)
    for (std::uint32_t x = 0; x < width; ++x) {
      const float u = float(x) / float(width), v = float(y) / float(height);
      const float r = 0.45f + 0.2f * std::sin(6.0f * u + 2.0f * v) + noise(random);
      const float g = 0.45f + 0.2f * std::cos(9.0f * v - 3.0f * u) + noise(random);
      const float b = 0.45f + 0.2f * std::sin(4.0f * (u + v)) + noise(random);
      image.pixels[std::size_t(y) * width + x] = glm::vec4(r, g, b, 1.0f);
    }
  return image;
}

RgbaImage boxBlur3(const RgbaImage& image) {
  RgbaImage out = image;
  const int w = int(image.width), h = int(image.height);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      glm::vec4 sum(0.0f);
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int sx = std::clamp(x + dx, 0, w - 1), sy = std::clamp(y + dy, 0, h - 1);
          sum += image.pixels[std::size_t(sy) * w + sx];
        }
      out.pixels[std::size_t(y) * w + x] = sum / 9.0f;
    }
  return out;
}

// SSIM straight from the definition: a full 2D Gaussian window at every valid position.
double referenceSsim(const RgbaImage& a, const RgbaImage& b) {
  const auto lum = [](const glm::vec4& p) { return 0.2126 * p.r + 0.7152 * p.g + 0.0722 * p.b; };
  const int w = int(a.width), h = int(a.height);
  const int kx = std::min(11, w), ky = std::min(11, h);
  std::vector<double> weights(std::size_t(kx) * ky);
  double total = 0.0;
  for (int j = 0; j < ky; ++j)
    for (int i = 0; i < kx; ++i) {
      const double dx = i - 0.5 * (kx - 1), dy = j - 0.5 * (ky - 1);
      total += weights[std::size_t(j) * kx + i] = std::exp(-(dx * dx + dy * dy) / (2.0 * 1.5 * 1.5));
    }
  double sum = 0.0;
  for (int top = 0; top + ky <= h; ++top)
    for (int left = 0; left + kx <= w; ++left) {
      double ma = 0, mb = 0, aa = 0, bb = 0, ab = 0;
      for (int j = 0; j < ky; ++j)
        for (int i = 0; i < kx; ++i) {
          const double wt = weights[std::size_t(j) * kx + i] / total;
          const std::size_t p = std::size_t(top + j) * w + std::size_t(left + i);
          const double va = lum(a.pixels[p]), vb = lum(b.pixels[p]);
          ma += wt * va, mb += wt * vb, aa += wt * va * va, bb += wt * vb * vb, ab += wt * va * vb;
        }
      const double c1 = 1e-4, c2 = 9e-4;
      sum += (2 * ma * mb + c1) * (2 * (ab - ma * mb) + c2) /
             ((ma * ma + mb * mb + c1) * ((aa - ma * ma) + (bb - mb * mb) + c2));
    }
  return sum / double((w - kx + 1) * (h - ky + 1));
}

TEST(ImageMetrics, IdenticalImagesDifferByNothing) {
  const RgbaImage a = patternImage(64, 48);
  const ImageDifference d = compareImages(a, a);
  EXPECT_EQ(d.rmse, 0.0);
  EXPECT_TRUE(std::isinf(d.psnr) && d.psnr > 0);
  EXPECT_DOUBLE_EQ(d.ssim, 1.0);
  EXPECT_EQ(d.holeFraction, 0.0);
  EXPECT_EQ(d.bloatFraction, 0.0);
  EXPECT_EQ(d.flipMean, 0.0);
  EXPECT_EQ(d.flipMax, 0.0);
  EXPECT_EQ(d.pixels, 64u * 48u);
  EXPECT_EQ(d.foregroundPixels, d.pixels);
  EXPECT_EQ(d.coverageA, double(d.pixels));
  EXPECT_EQ(d.coverageB, double(d.pixels));
  EXPECT_TRUE(std::isinf(d.foregroundPsnr));
}

TEST(ImageMetrics, ConstantOffsetGivesItsRmseAndPsnr) {
  const RgbaImage a = patternImage(40, 30);
  for (float offset : {0.001f, 0.01f, 0.1f}) {
    RgbaImage b = a;
    for (glm::vec4& p : b.pixels) p += glm::vec4(offset, offset, offset, 0.0f);
    const ImageDifference d = compareImages(a, b);
    EXPECT_NEAR(d.rmse, offset, 1e-6) << offset;
    EXPECT_NEAR(d.psnr, -20.0 * std::log10(double(offset)), 1e-3) << offset;
    EXPECT_LT(d.ssim, 1.0);
    EXPECT_GT(d.ssim, 0.9);  // the structure is all there; only the mean moved
    EXPECT_EQ(d.holeFraction, 0.0);
  }
}

TEST(ImageMetrics, NegativeImageHasLowSsim) {
  const RgbaImage a = patternImage(64, 64);
  RgbaImage b = a;
  for (glm::vec4& p : b.pixels) p = glm::vec4(1.0f - p.r, 1.0f - p.g, 1.0f - p.b, p.a);
  EXPECT_LT(compareImages(a, b).ssim, 0.2);
}

TEST(ImageMetrics, MildBlurKeepsMostOfTheStructure) {
  const RgbaImage a = patternImage(96, 80);
  const double ssim = compareImages(a, boxBlur3(a)).ssim;
  EXPECT_GT(ssim, 0.5);
  EXPECT_LT(ssim, 1.0);
}

TEST(ImageMetrics, SsimMatchesTheDefinition) {
  const RgbaImage a = patternImage(37, 23, 1);
  const RgbaImage b = boxBlur3(patternImage(37, 23, 2));
  EXPECT_NEAR(luminanceSsim(a, b), referenceSsim(a, b), 1e-12);
  // Sides shorter than the 11-pixel window use their whole length.
  const RgbaImage c = patternImage(6, 4, 3), e = patternImage(6, 4, 4);
  EXPECT_NEAR(luminanceSsim(c, e), referenceSsim(c, e), 1e-12);
  EXPECT_DOUBLE_EQ(luminanceSsim(c, c), 1.0);
  const RgbaImage one = patternImage(1, 1);
  EXPECT_DOUBLE_EQ(luminanceSsim(one, one), 1.0);
}

TEST(ImageMetrics, HolesAndBloatCountCoverageAgainstB) {
  // 4×4: B covers the left half (8 pixels); A misses two of them, covers one 0.4 and adds 1.5 on the right.
  const std::uint32_t w = 4, h = 4;
  RgbaImage a{w, h, std::vector<glm::vec4>(16, glm::vec4(0.0f))};
  RgbaImage b = a;
  for (std::uint32_t y = 0; y < h; ++y)
    for (std::uint32_t x = 0; x < 2; ++x) {
      b.pixels[y * w + x] = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
      a.pixels[y * w + x] = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
    }
  a.pixels[0 * w + 0] = glm::vec4(0.0f);                    // a whole hole
  a.pixels[1 * w + 0] = glm::vec4(0.0f);                    // another
  a.pixels[3 * w + 1] = glm::vec4(0.5f, 0.5f, 0.5f, 0.4f);  // 0.6 of a hole
  a.pixels[1 * w + 3] = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);  // bloat: surface where B has none
  a.pixels[2 * w + 3] = glm::vec4(0.0f, 0.0f, 0.0f, 0.5f);  // half a pixel of bloat
  const ImageDifference d = compareImages(a, b);
  EXPECT_DOUBLE_EQ(d.coverageB, 8.0);
  EXPECT_NEAR(d.coverageA, 5.4 + 1.5, 1e-6);
  EXPECT_NEAR(d.holes, 2.6, 1e-6);
  EXPECT_NEAR(d.holeFraction, 2.6 / 8.0, 1e-7);
  EXPECT_NEAR(d.bloat, 1.5, 1e-6);
  EXPECT_NEAR(d.bloatFraction, 1.5 / 8.0, 1e-7);
  EXPECT_EQ(d.foregroundPixels, 10u);  // the left half and the two bloated pixels

  const RgbaImage empty{w, h, std::vector<glm::vec4>(16, glm::vec4(0.0f))};
  const ImageDifference none = compareImages(a, empty);
  EXPECT_EQ(none.coverageB, 0.0);
  EXPECT_EQ(none.holeFraction, 0.0);
  EXPECT_EQ(none.bloatFraction, 0.0) << "relative to B's coverage, and B covers nothing";
}

TEST(ImageMetrics, BothImagesAreCompositedOverOneBackground) {
  // Colour behind alpha 0 is invisible: black and red backgrounds compare equal over any background.
  const std::uint32_t w = 8, h = 8;
  RgbaImage a{w, h, std::vector<glm::vec4>(64, glm::vec4(0.0f, 0.0f, 0.0f, 0.0f))};
  RgbaImage b{w, h, std::vector<glm::vec4>(64, glm::vec4(1.0f, 0.0f, 0.0f, 0.0f))};
  EXPECT_EQ(compareImages(a, b).rmse, 0.0);
  // A half-covered grey pixel over white is (0.5·0.2 + 0.5·1) = 0.6 in every channel; B's opaque 0.6
  // grey is the same picture.
  a.pixels[9] = glm::vec4(0.2f, 0.2f, 0.2f, 0.5f);
  b.pixels[9] = glm::vec4(0.6f, 0.6f, 0.6f, 1.0f);
  const ImageDifference white = compareImages(a, b);
  EXPECT_NEAR(white.rmse, 0.0, 1e-7);
  EXPECT_NEAR(white.holeFraction, 0.5, 1e-7);  // coverage still counts apart from colour
  // Over black the same pair differs by 0.5 in one pixel's three channels.
  const ImageDifference black = compareImages(a, b, {.background = glm::vec3(0.0f)});
  EXPECT_NEAR(black.rmse, std::sqrt(3 * 0.25 / (3.0 * 64)), 1e-7);
}

TEST(ImageMetrics, ForegroundPsnrIsNotDilutedByTheSharedBackground) {
  // 100×100, background everywhere but a 10×10 square both cover; A's square is 0.1 brighter.
  const std::uint32_t w = 100, h = 100;
  RgbaImage a{w, h, std::vector<glm::vec4>(w * h, glm::vec4(0.0f))};
  RgbaImage b = a;
  for (std::uint32_t y = 40; y < 50; ++y)
    for (std::uint32_t x = 40; x < 50; ++x) {
      a.pixels[y * w + x] = glm::vec4(0.6f, 0.6f, 0.6f, 1.0f);
      b.pixels[y * w + x] = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
    }
  const ImageDifference d = compareImages(a, b);
  EXPECT_EQ(d.foregroundPixels, 100u);
  EXPECT_NEAR(d.foregroundPsnr, 20.0, 1e-4);  // mse 0.01 over the square
  EXPECT_NEAR(d.psnr, 40.0, 1e-4);            // the same error over 100 times the pixels
  EXPECT_GT(d.flipForegroundMean, 10.0 * d.flipMean * 0.9) << "FLIP over the foreground is not diluted either";
  EXPECT_GT(d.flipMean, 0.0);
  EXPECT_EQ(d.holeFraction, 0.0);
  EXPECT_EQ(d.bloatFraction, 0.0);
}

TEST(ImageMetrics, FlipIsComputedOnTheCompositedPair) {
  const RgbaImage a = patternImage(64, 48, 1);
  const RgbaImage b = boxBlur3(patternImage(64, 48, 2));
  const ImageDifference d = compareImages(a, b, {.keepFlipMap = true});
  ASSERT_EQ(d.flipMap.size(), a.pixelCount());
  std::vector<glm::vec3> ra, rb;
  for (std::size_t i = 0; i < a.pixelCount(); ++i) {
    ra.push_back(glm::vec3(a.pixels[i]));
    rb.push_back(glm::vec3(b.pixels[i]));
  }
  const FlipResult flip = computeFlip(rb, ra, a.width, a.height);  // opaque: compositing changes nothing
  EXPECT_EQ(d.flipMean, flip.mean);
  EXPECT_EQ(d.flipMedian, flip.median);
  EXPECT_EQ(d.flipMax, flip.max);
  EXPECT_NEAR(d.flipForegroundMean, flip.mean, 1e-9);  // every pixel is foreground
  EXPECT_TRUE(compareImages(a, b).flipMap.empty()) << "the map is kept only when asked for";
  EXPECT_EQ(compareImages(a, b, {.flip = false}).flipMean, 0.0);
}

TEST(ImageMetrics, NonFiniteValuesCountAsZero) {
  const RgbaImage b = patternImage(32, 24, 3);
  RgbaImage bad = b, zeroed = b;
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  bad.pixels[5] = glm::vec4(nan, 0.5f, -inf, 1.0f);
  zeroed.pixels[5] = glm::vec4(0.0f, 0.5f, 0.0f, 1.0f);
  bad.pixels[40] = glm::vec4(0.3f, 0.3f, 0.3f, nan);  // coverage NaN: background
  zeroed.pixels[40] = glm::vec4(0.3f, 0.3f, 0.3f, 0.0f);
  const ImageDifference d = compareImages(bad, b), expected = compareImages(zeroed, b);
  for (double value : {d.rmse, d.psnr, d.foregroundPsnr, d.ssim, d.flipMean, d.holeFraction, d.bloatFraction})
    EXPECT_TRUE(std::isfinite(value));
  EXPECT_EQ(d.rmse, expected.rmse);
  EXPECT_EQ(d.flipMean, expected.flipMean);
  EXPECT_EQ(d.holes, expected.holes);
  EXPECT_EQ(d.foregroundPixels, expected.foregroundPixels);
}

TEST(ImageMetrics, ThresholdsReportEveryLimitBroken) {
  ImageDifference d;
  d.flipMean = 0.05;
  d.psnr = 30.0;
  d.foregroundPsnr = 20.0;
  d.holeFraction = 0.01;
  d.bloatFraction = 0.2;
  EXPECT_TRUE(failedThresholds(d, {}).empty()) << "no limits, nothing fails";
  const ImageThresholds passing{
      .maxFlip = 0.05, .minPsnr = 30.0, .minForegroundPsnr = 20.0, .maxHoles = 0.01, .maxBloat = 0.2};
  EXPECT_TRUE(failedThresholds(d, passing).empty()) << "a value equal to its limit passes";
  const ImageThresholds strict{
      .maxFlip = 0.04, .minPsnr = 31.0, .minForegroundPsnr = 19.0, .maxHoles = 0.02, .maxBloat = 0.1};
  const std::vector<ThresholdFailure> failures = failedThresholds(d, strict);
  ASSERT_EQ(failures.size(), 3u);
  EXPECT_EQ(failures[0].option, "--max-flip");
  EXPECT_EQ(failures[0].value, 0.05);
  EXPECT_EQ(failures[0].limit, 0.04);
  EXPECT_EQ(failures[1].option, "--min-psnr");
  EXPECT_EQ(failures[2].option, "--max-bloat");
  d.flipMean = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(failedThresholds(d, {.maxFlip = 1.0}).size(), 1u) << "NaN breaks its limit";
  d.psnr = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(failedThresholds(d, {.minPsnr = 1000.0}).empty()) << "identical images pass any PSNR limit";
}

TEST(ImageMetrics, SizeMismatchThrows) {
  EXPECT_THROW(compareImages(patternImage(8, 8), patternImage(8, 9)), std::invalid_argument);
  EXPECT_THROW(compareImages(patternImage(8, 8), patternImage(9, 8)), std::invalid_argument);
  RgbaImage broken = patternImage(8, 8);
  broken.pixels.pop_back();
  EXPECT_THROW(compareImages(broken, broken), std::invalid_argument);
}

TEST(ImageMetrics, SameNumbersForAnyThreadCount) {
  const RgbaImage a = patternImage(301, 157, 5);
  const RgbaImage b = boxBlur3(patternImage(301, 157, 6));
  ImageDifference one, many, some;
  runWithThreads(1, [&] { one = compareImages(a, b); });
  runWithThreads(0, [&] { many = compareImages(a, b); });
  runWithThreads(3, [&] { some = compareImages(a, b); });
  for (const ImageDifference* d : {&many, &some}) {
    EXPECT_EQ(d->rmse, one.rmse);
    EXPECT_EQ(d->psnr, one.psnr);
    EXPECT_EQ(d->ssim, one.ssim);
    EXPECT_EQ(d->flipMean, one.flipMean);
    EXPECT_EQ(d->foregroundPsnr, one.foregroundPsnr);
    EXPECT_EQ(d->holes, one.holes);
  }
}

// --- `pbs compare` over files written here with OpenImageIO ---

void writeFile8(const std::filesystem::path& file, std::uint32_t width, std::uint32_t height, int channels,
                const std::vector<std::uint8_t>& values) {
  auto out = OIIO::ImageOutput::create(file.string());
  ASSERT_TRUE(out);
  OIIO::ImageSpec spec(int(width), int(height), channels, OIIO::TypeDesc::UINT8);
  spec.attribute("oiio:UnassociatedAlpha", 1);  // store the colour as given, as pbs does
  ASSERT_TRUE(out->open(file.string(), spec) && out->write_image(OIIO::TypeDesc::UINT8, values.data()) && out->close());
}

// Quantises to 8 bits, writes the PNG, and returns the image as the reader should see it.
RgbaImage writePng(const std::filesystem::path& file, const RgbaImage& image) {
  std::vector<std::uint8_t> values;
  RgbaImage seen = image;
  for (glm::vec4& p : seen.pixels)
    for (int c = 0; c < 4; ++c) {
      const auto v = std::uint8_t(std::lround(std::clamp(p[c], 0.0f, 1.0f) * 255.0f));
      values.push_back(v);
      p[c] = float(v) / 255.0f;
    }
  writeFile8(file, image.width, image.height, 4, values);
  return seen;
}

void writeExr(const std::filesystem::path& file, const RgbaImage& image) {
  auto out = OIIO::ImageOutput::create(file.string());
  ASSERT_TRUE(out);
  const OIIO::ImageSpec spec(int(image.width), int(image.height), 4, OIIO::TypeDesc::FLOAT);
  ASSERT_TRUE(out->open(file.string(), spec) && out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data()) &&
              out->close());
}

nlohmann::json compareJson(const std::filesystem::path& a, const std::filesystem::path& b) {
  const CommandResult r = runPbs("compare '" + a.string() + "' '" + b.string() + "' --json");
  EXPECT_EQ(r.status, 0) << r.err;
  return nlohmann::json::parse(r.out);
}

// Surface everywhere but a disc in the middle, which is background (black, alpha 0).
RgbaImage withHole(RgbaImage image, float radius) {
  for (std::uint32_t y = 0; y < image.height; ++y)
    for (std::uint32_t x = 0; x < image.width; ++x) {
      const float dx = float(x) - 0.5f * float(image.width), dy = float(y) - 0.5f * float(image.height);
      if (dx * dx + dy * dy < radius * radius) image.pixels[std::size_t(y) * image.width + x] = glm::vec4(0.0f);
    }
  return image;
}

void expectJsonMatches(const nlohmann::json& j, const ImageDifference& d, const RgbaImage& a, double tolerance) {
  EXPECT_NEAR(j.at("rmse").get<double>(), d.rmse, tolerance);
  EXPECT_NEAR(j.at("psnr").get<double>(), d.psnr, tolerance * 1e4);
  EXPECT_NEAR(j.at("ssim").get<double>(), d.ssim, tolerance);
  EXPECT_NEAR(j.at("hole_fraction").get<double>(), d.holeFraction, 1e-15);
  EXPECT_NEAR(j.at("bloat_fraction").get<double>(), d.bloatFraction, 1e-15);
  EXPECT_NEAR(j.at("flip_mean").get<double>(), d.flipMean, tolerance);
  EXPECT_NEAR(j.at("flip_foreground_mean").get<double>(), d.flipForegroundMean, tolerance);
  EXPECT_EQ(j.at("width").get<std::uint32_t>(), a.width);
  EXPECT_EQ(j.at("height").get<std::uint32_t>(), a.height);
  EXPECT_EQ(j.at("coverage_a").get<double>(), d.coverageA);
  EXPECT_EQ(j.at("coverage_b").get<double>(), d.coverageB);
  EXPECT_TRUE(j.at("passed").get<bool>());
}

TEST(CompareCommand, PngNumbersMatchTheLibrary) {
  ScratchDir dir;
  RgbaImage pattern = withHole(patternImage(48, 36, 1), 6.0f);
  pattern.pixels[3] = glm::vec4(0.8f, 0.6f, 0.4f, 0.0f);  // colour behind alpha 0 is not seen
  pattern.pixels[4] = glm::vec4(0.8f, 0.6f, 0.4f, 0.6f);  // straight colour, not premultiplied
  const RgbaImage a = writePng(dir / "a.png", pattern);
  const RgbaImage b = writePng(dir / "b.png", boxBlur3(patternImage(48, 36, 1)));
  const ImageDifference d = compareImages(a, b);
  ASSERT_GT(d.holes, 0.0);
  expectJsonMatches(compareJson(dir / "a.png", dir / "b.png"), d, a, 1e-6);

  const CommandResult text = runPbs("compare '" + (dir / "a.png").string() + "' '" + (dir / "b.png").string() + "'");
  EXPECT_EQ(text.status, 0) << text.err;
  EXPECT_EQ(std::count(text.out.begin(), text.out.end(), '\n'), 1) << text.out;
  EXPECT_EQ(text.out.rfind("flip ", 0), 0u) << text.out;
  for (const char* part : {"  psnr ", " dB (foreground ", "  ssim ", "  holes ", "  bloat ", "(48x36; coverage A "})
    EXPECT_NE(text.out.find(part), std::string::npos) << part << " in " << text.out;
}

TEST(CompareCommand, IdenticalFilesGiveNullPsnr) {
  ScratchDir dir;
  writePng(dir / "a.png", patternImage(20, 20));
  const nlohmann::json j = compareJson(dir / "a.png", dir / "a.png");
  EXPECT_EQ(j.at("rmse").get<double>(), 0.0);
  EXPECT_TRUE(j.at("psnr").is_null());
  EXPECT_DOUBLE_EQ(j.at("ssim").get<double>(), 1.0);
  EXPECT_EQ(j.at("hole_fraction").get<double>(), 0.0);
  const CommandResult text = runPbs("compare '" + (dir / "a.png").string() + "' '" + (dir / "a.png").string() + "'");
  EXPECT_NE(text.out.find("psnr inf dB"), std::string::npos) << text.out;
}

TEST(CompareCommand, ExrFloatsArriveUnchanged) {
  ScratchDir dir;
  RgbaImage a = withHole(patternImage(33, 21, 8), 4.0f);
  a.pixels[5] = glm::vec4(3.75f, -0.125f, 1e-7f, 1.0f);  // HDR, negative and tiny values survive
  const RgbaImage b = boxBlur3(patternImage(33, 21, 9));
  writeExr(dir / "a.exr", a);
  writeExr(dir / "b.exr", b);
  expectJsonMatches(compareJson(dir / "a.exr", dir / "b.exr"), compareImages(a, b), a, 1e-12);
}

TEST(CompareCommand, GreyAndAlphaFreeFilesAreSurfaceColour) {
  ScratchDir dir;
  // The same grey written as one channel, as RGB and as opaque RGBA: no difference at all.
  const std::uint32_t w = 16, h = 12;
  std::vector<std::uint8_t> grey, rgb, rgba;
  for (std::uint32_t i = 0; i < w * h; ++i) {
    const auto v = std::uint8_t((i * 37) % 256);
    grey.push_back(v);
    rgb.insert(rgb.end(), {v, v, v});
    rgba.insert(rgba.end(), {v, v, v, 255});
  }
  writeFile8(dir / "grey.png", w, h, 1, grey);
  writeFile8(dir / "rgb.png", w, h, 3, rgb);
  writeFile8(dir / "rgba.png", w, h, 4, rgba);
  for (const char* other : {"rgb.png", "rgba.png"}) {
    const nlohmann::json j = compareJson(dir / "grey.png", dir / other);
    EXPECT_EQ(j.at("rmse").get<double>(), 0.0) << other;
    EXPECT_EQ(j.at("coverage_a").get<double>(), double(w * h)) << other;
    EXPECT_EQ(j.at("coverage_b").get<double>(), double(w * h)) << other;
  }
}

TEST(CompareCommand, LimitsMakeAnImageTestWithItsOwnExitStatus) {
  ScratchDir dir;
  writePng(dir / "a.png", withHole(patternImage(40, 30, 1), 5.0f));
  writePng(dir / "b.png", patternImage(40, 30, 1));
  const std::string pair = "compare '" + (dir / "a.png").string() + "' '" + (dir / "b.png").string() + "'";
  const nlohmann::json measured = compareJson(dir / "a.png", dir / "b.png");
  const double flip = measured.at("flip_mean").get<double>();
  const double holes = measured.at("hole_fraction").get<double>();
  ASSERT_GT(flip, 0.0);
  ASSERT_GT(holes, 0.0);

  const CommandResult passes = runPbs(pair + " --max-flip " + std::to_string(flip * 1.01) + " --max-holes 1");
  EXPECT_EQ(passes.status, 0) << passes.err;
  EXPECT_TRUE(passes.err.empty()) << passes.err;

  const CommandResult fails = runPbs(pair + " --max-flip " + std::to_string(flip * 0.5) + " --max-holes 1 --json");
  EXPECT_EQ(fails.status, 3) << "3: a limit broken, distinct from 1 (bad input) and 2 (bad usage)";
  EXPECT_EQ(fails.err.rfind("fail: --max-flip ", 0), 0u) << fails.err;
  EXPECT_EQ(std::count(fails.err.begin(), fails.err.end(), '\n'), 1) << fails.err;
  const nlohmann::json report = nlohmann::json::parse(fails.out);
  EXPECT_FALSE(report.at("passed").get<bool>());
  ASSERT_EQ(report.at("failed").size(), 1u);
  EXPECT_EQ(report.at("failed")[0].at("option"), "--max-flip");

  const CommandResult twoFail = runPbs(pair + " --max-holes 0 --min-foreground-psnr 200");
  EXPECT_EQ(twoFail.status, 3);
  EXPECT_EQ(std::count(twoFail.err.begin(), twoFail.err.end(), '\n'), 2) << twoFail.err;

  const std::filesystem::path map = dir / "flip.png";
  EXPECT_EQ(runPbs(pair + " --flip-map '" + map.string() + "'").status, 0);
  auto in = OIIO::ImageInput::open(map.string());
  ASSERT_TRUE(in) << "the FLIP map is written";
  EXPECT_EQ(in->spec().width, 40);
  EXPECT_EQ(in->spec().height, 30);

  EXPECT_EQ(runPbs(pair + " --background 2,0,0").status, 2) << "a background outside [0, 1] is bad usage";
  EXPECT_EQ(runPbs(pair + " --max-flip -1").status, 2);
}

TEST(CompareCommand, BadInputsGiveOneErrorLine) {
  ScratchDir dir;
  writePng(dir / "a.png", patternImage(20, 20));
  writePng(dir / "b.png", patternImage(20, 21));
  writeFile(dir / "text.png", "not an image\n");
  const auto expectError = [](const CommandResult& r, const std::string& start) {
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_EQ(r.err.rfind("error: " + start, 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  };
  const std::string a = (dir / "a.png").string(), b = (dir / "b.png").string();
  expectError(runPbs("compare '" + a + "' '" + b + "'"), "A and B differ in size (" + a + ": 20x20, " + b + ": 20x21)");
  const std::string missing = (dir / "missing.png").string();
  expectError(runPbs("compare '" + missing + "' '" + a + "' --json"), missing + ": cannot read image: no such file");
  const std::string text = (dir / "text.png").string();
  expectError(runPbs("compare '" + a + "' '" + text + "'"), text + ": cannot read image: ");
  const std::string folder = dir.path().string();
  expectError(runPbs("compare '" + a + "' '" + folder + "'"), folder + ": cannot read image: not a file");
}

// --- images pbs writes: PNG through libpng in the process, other formats through the plug-in ---

std::vector<std::uint8_t> readPixels8(const std::filesystem::path& file, int& channels) {
  auto in = OIIO::ImageInput::open(file.string());
  EXPECT_TRUE(in) << file;
  if (!in) return {};
  const OIIO::ImageSpec& spec = in->spec();
  channels = spec.nchannels;
  std::vector<std::uint8_t> values(std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(spec.nchannels));
  EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, values.data()));
  return values;
}

TEST(ImageFiles, PngFromLibpngHoldsThePixelsTheTiffPlugInWrites) {
  ScratchDir dir;
  const std::string view = "render default --size 96x64 -o '";
  ASSERT_EQ(runPbs(view + (dir / "frame.png").string() + "'").status, 0);
  ASSERT_EQ(runPbs(view + (dir / "frame.tif").string() + "'").status, 0);
  int pngChannels = 0, tifChannels = 0;
  const std::vector<std::uint8_t> png = readPixels8(dir / "frame.png", pngChannels);
  const std::vector<std::uint8_t> tif = readPixels8(dir / "frame.tif", tifChannels);
  EXPECT_EQ(pngChannels, 4);
  EXPECT_EQ(tifChannels, 4);
  ASSERT_EQ(png.size(), std::size_t(96 * 64 * 4));
  EXPECT_EQ(png, tif);
  std::size_t covered = 0;
  for (std::size_t alpha = 3; alpha < png.size(); alpha += 4) covered += png[alpha] != 0;
  EXPECT_GT(covered, 100u) << "the frame shows the scene";
}

TEST(ImageFiles, PngThatCannotBeWrittenIsOneErrorLine) {
  ScratchDir dir;
  writeFile(dir / "plain", "a file, not a folder\n");
  const std::string target = (dir / "plain" / "frame.png").string();  // not a folder, even for root
  const CommandResult r = runPbs("render default --size 32x32 -o '" + target + "'");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err.rfind("error: " + target + ": cannot write image: ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(readFile(dir / "plain"), "a file, not a folder\n");
}

}  // namespace
}  // namespace pbs::test
