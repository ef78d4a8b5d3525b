// LDR-FLIP (raster/flip.hpp): exact zeros, locality, the observer's distance, hand-computed colour errors, determinism,
// the map's colours.
#include <pbs/raster/flip.hpp>
#include <pbs/raster/thread_arena.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

namespace pbs::test {
namespace {

std::vector<glm::vec3> randomImage(std::uint32_t width, std::uint32_t height, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<glm::vec3> image(std::size_t(width) * height);
  for (glm::vec3& p : image) p = glm::vec3(unit(random), unit(random), unit(random));
  return image;
}

std::vector<glm::vec3> uniformImage(std::uint32_t width, std::uint32_t height, glm::vec3 colour) {
  return std::vector<glm::vec3>(std::size_t(width) * height, colour);
}

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// ---- The colour error of two flat colours, straight from the paper's formulas, in double. ----
// A flat image filters to itself (the filters are normalised) and has no edges or points, so every
// pixel's FLIP is this ΔEc.

double decodeSrgb(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

// Linear sRGB to XYZ (IEC 61966-2-1 primaries, D65), as usually tabulated to seven places.
constexpr double kRgbToXyz[3][3] = {
    {0.4123908, 0.3575843, 0.1804808}, {0.2126390, 0.7151687, 0.0721923}, {0.0193308, 0.1191948, 0.9505322}};

std::array<double, 3> linearToXyz(std::array<double, 3> rgb) {
  std::array<double, 3> xyz{};
  for (int i = 0; i < 3; ++i) xyz[i] = kRgbToXyz[i][0] * rgb[0] + kRgbToXyz[i][1] * rgb[1] + kRgbToXyz[i][2] * rgb[2];
  return xyz;
}

// CIELAB relative to the XYZ of linear white, then a and b scaled by 0.01·L (Hunt).
std::array<double, 3> huntLab(std::array<double, 3> linearRgb) {
  const std::array<double, 3> xyz = linearToXyz(linearRgb);
  const std::array<double, 3> white = linearToXyz({1.0, 1.0, 1.0});
  const auto f = [](double t) {
    const double delta = 6.0 / 29.0;
    return t > delta * delta * delta ? std::cbrt(t) : t / (3.0 * delta * delta) + 4.0 / 29.0;
  };
  const double fx = f(xyz[0] / white[0]), fy = f(xyz[1] / white[1]), fz = f(xyz[2] / white[2]);
  const double l = 116.0 * fy - 16.0;
  return {l, 0.01 * l * 500.0 * (fx - fy), 0.01 * l * 200.0 * (fy - fz)};
}

double hyab(std::array<double, 3> p, std::array<double, 3> q) {
  return std::abs(p[0] - q[0]) + std::hypot(p[1] - q[1], p[2] - q[2]);
}

double colourErrorOfFlatColours(glm::vec3 srgbA, glm::vec3 srgbB) {
  const auto lab = [](glm::vec3 c) { return huntLab({decodeSrgb(c.r), decodeSrgb(c.g), decodeSrgb(c.b)}); };
  const double cmax = std::pow(hyab(huntLab({0.0, 1.0, 0.0}), huntLab({0.0, 0.0, 1.0})), 0.7);
  const double pc = 0.4, pt = 0.95;
  const double e = std::pow(hyab(lab(srgbA), lab(srgbB)), 0.7);
  return e < pc * cmax ? pt / (pc * cmax) * e : pt + (e - pc * cmax) / (cmax - pc * cmax) * (1.0 - pt);
}

// The largest kernel radius at a viewing distance: the colour filters' (set by the widest
// contrast-sensitivity Gaussian, b = 0.04) or the feature detectors' (3σ, σ = 0.041 degrees).
int influenceRadius(double pixelsPerDegree) {
  const double pi = std::numbers::pi;
  const int colour = int(std::ceil(3.0 * std::sqrt(0.04 / (2.0 * pi * pi)) * pixelsPerDegree));
  const int features = int(std::ceil(3.0 * 0.5 * 0.082 * pixelsPerDegree));
  return std::max(colour, features);
}

double linearLuminance(const std::uint8_t* rgba) {
  return 0.2126 * decodeSrgb(rgba[0] / 255.0) + 0.7152 * decodeSrgb(rgba[1] / 255.0) +
         0.0722 * decodeSrgb(rgba[2] / 255.0);
}

}  // namespace

TEST(Flip, IdenticalImagesScoreExactlyZero) {
  const std::vector<glm::vec3> image = randomImage(53, 37, 1);
  const FlipResult r = computeFlip(image, image, 53, 37, kDefaultPixelsPerDegree, true);
  EXPECT_EQ(r.mean, 0.0);
  EXPECT_EQ(r.median, 0.0);
  EXPECT_EQ(r.max, 0.0);
  ASSERT_EQ(r.map.size(), image.size());
  EXPECT_TRUE(std::all_of(r.map.begin(), r.map.end(), [](float v) { return v == 0.0f; }));
}

TEST(Flip, OnePixelChangeReachesExactlyTheKernelRadius) {
  const std::uint32_t w = 61, h = 57, cx = 30, cy = 27;
  const std::vector<glm::vec3> reference = randomImage(w, h, 2);
  std::vector<glm::vec3> test = reference;
  test[std::size_t(cy) * w + cx] = glm::vec3(0.0f, 0.0f, 1.0f);
  const int radius = influenceRadius(kDefaultPixelsPerDegree);
  ASSERT_EQ(radius, 10) << "the paper's observer: 10 pixels (colour), 9 (features)";
  const FlipResult r = computeFlip(reference, test, w, h, kDefaultPixelsPerDegree, true);
  for (std::uint32_t y = 0; y < h; ++y)
    for (std::uint32_t x = 0; x < w; ++x) {
      const int distance = std::max(std::abs(int(x) - int(cx)), std::abs(int(y) - int(cy)));
      if (distance > radius) {
        ASSERT_EQ(r.map[std::size_t(y) * w + x], 0.0f) << x << ", " << y;
      }
    }
  EXPECT_GT(r.map[std::size_t(cy) * w + cx], 0.1f);
  // The blue-yellow kernel's outermost taps still carry weight: the change is felt at the radius.
  EXPECT_GT(r.map[std::size_t(cy) * w + cx + radius], 0.0f);
  EXPECT_GT(r.map[std::size_t(cy - radius) * w + cx], 0.0f);
  EXPECT_EQ(r.max, *std::max_element(r.map.begin(), r.map.end()));
}

TEST(Flip, FineDetailMattersLessFromFarther) {
  // A one-pixel checkerboard and noise against the grey of the checkerboard's mean light (linear 0.5):
  // the farther the observer (more pixels per degree), the more the eye blurs the detail away.
  const std::uint32_t w = 128, h = 128;
  std::vector<glm::vec3> checker(std::size_t(w) * h);
  for (std::uint32_t y = 0; y < h; ++y)
    for (std::uint32_t x = 0; x < w; ++x) checker[std::size_t(y) * w + x] = glm::vec3(float((x + y) % 2));
  std::vector<glm::vec3> noise = randomImage(w, h, 3);
  for (glm::vec3& p : noise) p = glm::vec3(p.r);  // grey noise
  const std::vector<glm::vec3> grey = uniformImage(w, h, glm::vec3(0.735357f));
  double checkerBefore = 2.0, noiseBefore = 2.0;
  for (double ppd : {10.0, 20.0, 40.0, kDefaultPixelsPerDegree, 120.0}) {
    const double checkerMean = computeFlip(checker, grey, w, h, ppd).mean;
    const double noiseMean = computeFlip(noise, grey, w, h, ppd).mean;
    EXPECT_LT(checkerMean, checkerBefore) << ppd << " pixels per degree";
    EXPECT_LT(noiseMean, noiseBefore) << ppd << " pixels per degree";
    checkerBefore = checkerMean;
    noiseBefore = noiseMean;
  }
  EXPECT_LT(checkerBefore, 0.01) << "at 120 pixels per degree the checkerboard is grey";
}

TEST(Flip, FlatColoursScoreTheirColourErrorFromThePaper) {
  const std::array<std::array<glm::vec3, 2>, 6> pairs = {{
      {glm::vec3(0.2f), glm::vec3(0.25f)},
      {glm::vec3(0.8f, 0.1f, 0.1f), glm::vec3(0.9f, 0.5f, 0.1f)},
      {glm::vec3(0.3f, 0.6f, 0.9f), glm::vec3(0.35f, 0.55f, 0.8f)},
      {glm::vec3(0.02f, 0.01f, 0.03f), glm::vec3(0.0f)},  // near black: the linear part of CIELAB
      {glm::vec3(1.0f), glm::vec3(0.0f)},
      {glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(0.0f, 0.0f, 1.0f)},  // the largest distance: 1
  }};
  const std::uint32_t w = 13, h = 9;
  for (const auto& [a, b] : pairs) {
    const double expected = colourErrorOfFlatColours(a, b);
    const FlipResult r = computeFlip(uniformImage(w, h, a), uniformImage(w, h, b), w, h, kDefaultPixelsPerDegree, true);
    EXPECT_NEAR(r.mean, expected, 2e-6) << a.r << " " << a.g << " " << a.b << " vs " << b.r << " " << b.g << " " << b.b;
    EXPECT_NEAR(r.median, expected, 2e-6);
    EXPECT_NEAR(r.max, expected, 2e-6);
    const auto [low, high] = std::minmax_element(r.map.begin(), r.map.end());
    EXPECT_EQ(*low, *high) << "a flat pair is flat everywhere, borders included";
  }
  EXPECT_NEAR(colourErrorOfFlatColours(glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(0.0f, 0.0f, 1.0f)), 1.0, 1e-12);
}

TEST(Flip, SwappingReferenceAndTestChangesNothing) {
  // Every term of LDR-FLIP is a distance (HyAB, |edge − edge|, |point − point|).
  const std::vector<glm::vec3> a = randomImage(40, 30, 4);
  std::vector<glm::vec3> b = a;
  for (std::size_t i = 0; i < b.size(); i += 3) b[i] = glm::vec3(1.0f) - b[i];
  const FlipResult ab = computeFlip(a, b, 40, 30, kDefaultPixelsPerDegree, true);
  const FlipResult ba = computeFlip(b, a, 40, 30, kDefaultPixelsPerDegree, true);
  EXPECT_TRUE(sameBits(ab.map, ba.map));
  EXPECT_EQ(ab.mean, ba.mean);
}

TEST(Flip, TheSameColourShiftCountsForLessInTheDark) {
  // The Hunt adjustment scales chroma by lightness: a red-green shift of the same linear size is less
  // visible between dark colours than between bright ones.
  const std::uint32_t w = 8, h = 8;
  const auto error = [&](float level) {
    const float shift = 0.3f * level;
    const auto encode = [](float linear) {
      return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
    };
    const glm::vec3 a(encode(level + shift), encode(level), encode(level));
    const glm::vec3 b(encode(level), encode(level + shift), encode(level));
    return computeFlip(uniformImage(w, h, a), uniformImage(w, h, b), w, h).mean;
  };
  EXPECT_LT(error(0.02f), error(0.2f));
  EXPECT_LT(error(0.2f), error(0.7f));
}

TEST(Flip, BitIdenticalForAnyThreadCount) {
  const std::uint32_t w = 131, h = 77;
  const std::vector<glm::vec3> a = randomImage(w, h, 5);
  std::vector<glm::vec3> b = a;
  std::mt19937 random(6);
  std::normal_distribution<float> jitter(0.0f, 0.05f);
  for (glm::vec3& p : b) p += glm::vec3(jitter(random), jitter(random), jitter(random));
  FlipResult one, two, four;
  runWithThreads(1, [&] { one = computeFlip(a, b, w, h, kDefaultPixelsPerDegree, true); });
  runWithThreads(2, [&] { two = computeFlip(a, b, w, h, kDefaultPixelsPerDegree, true); });
  runWithThreads(4, [&] { four = computeFlip(a, b, w, h, kDefaultPixelsPerDegree, true); });
  EXPECT_TRUE(sameBits(one.map, two.map));
  EXPECT_TRUE(sameBits(one.map, four.map));
  for (const FlipResult* r : {&two, &four}) {
    EXPECT_EQ(one.mean, r->mean);
    EXPECT_EQ(one.median, r->median);
    EXPECT_EQ(one.max, r->max);
  }
}

TEST(Flip, PoolsTheMapIntoMeanMedianAndMax) {
  // Even and odd counts (an even count's median is the mean of the middle two), and a map mostly of
  // zeros, where the middle values repeat.
  const auto check = [](std::uint32_t w, std::uint32_t h, const std::vector<glm::vec3>& a,
                        const std::vector<glm::vec3>& b) {
    const FlipResult r = computeFlip(a, b, w, h, kDefaultPixelsPerDegree, true);
    std::vector<float> sorted = r.map;
    std::sort(sorted.begin(), sorted.end());
    double sum = 0.0;
    for (float v : sorted) sum += v;
    EXPECT_NEAR(r.mean, sum / double(sorted.size()), 1e-12);
    const std::size_t middle = sorted.size() / 2;
    const double median =
        sorted.size() % 2 == 1 ? double(sorted[middle]) : 0.5 * (double(sorted[middle - 1]) + double(sorted[middle]));
    EXPECT_EQ(r.median, median) << w << "x" << h;
    EXPECT_EQ(r.max, sorted.back());
    EXPECT_GE(sorted.front(), 0.0f);
    EXPECT_LE(sorted.back(), 1.0f);
    const FlipResult withoutMap = computeFlip(a, b, w, h);
    EXPECT_TRUE(withoutMap.map.empty()) << "the map is kept only when asked for";
    EXPECT_EQ(withoutMap.mean, r.mean);
    EXPECT_EQ(withoutMap.median, r.median);
  };
  check(20, 15, randomImage(20, 15, 7), randomImage(20, 15, 8));
  check(21, 15, randomImage(21, 15, 7), randomImage(21, 15, 8));
  std::vector<glm::vec3> spot = randomImage(50, 41, 14);
  for (std::size_t i = 0; i < 300; ++i) spot[i] = glm::vec3(0.0f, 0.0f, 1.0f);  // the top rows differ
  check(50, 41, randomImage(50, 41, 14), spot);
}

TEST(Flip, ValuesOutsideTheDisplayRangeAreClampedAndNanIsBlack) {
  const std::uint32_t w = 24, h = 18;
  const std::vector<glm::vec3> reference = randomImage(w, h, 9);
  std::vector<glm::vec3> wild = randomImage(w, h, 10);
  std::vector<glm::vec3> tame = wild;
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const std::array<std::pair<float, float>, 5> values = {
      {{nan, 0.0f}, {inf, 1.0f}, {-inf, 0.0f}, {2.5f, 1.0f}, {-0.3f, 0.0f}}};
  for (std::size_t i = 0; i < values.size(); ++i) {
    wild[7 * i + 3] = glm::vec3(values[i].first, 0.5f, values[i].first);
    tame[7 * i + 3] = glm::vec3(values[i].second, 0.5f, values[i].second);
  }
  const FlipResult a = computeFlip(reference, wild, w, h, kDefaultPixelsPerDegree, true);
  const FlipResult b = computeFlip(reference, tame, w, h, kDefaultPixelsPerDegree, true);
  EXPECT_TRUE(sameBits(a.map, b.map));
  EXPECT_TRUE(std::isfinite(a.mean));
}

TEST(Flip, EmptyImagesScoreZero) {
  const std::vector<glm::vec3> none;
  for (auto [w, h] : {std::pair{0u, 0u}, std::pair{0u, 7u}, std::pair{5u, 0u}}) {
    const FlipResult r = computeFlip(none, none, w, h, kDefaultPixelsPerDegree, true);
    EXPECT_EQ(r.mean, 0.0);
    EXPECT_EQ(r.median, 0.0);
    EXPECT_EQ(r.max, 0.0);
    EXPECT_TRUE(r.map.empty());
  }
}

TEST(Flip, TinyAndHugeViewingDistancesStayFinite) {
  // Images smaller than the kernels, and kernels too fine to have a negative or positive lobe.
  const std::uint32_t w = 3, h = 2;
  const std::vector<glm::vec3> a = randomImage(w, h, 11);
  const std::vector<glm::vec3> b = randomImage(w, h, 12);
  for (double ppd : {1e-6, 0.1, 1.0, 500.0, kMaxPixelsPerDegree}) {
    const FlipResult r = computeFlip(a, b, w, h, ppd, true);
    for (float v : r.map) {
      EXPECT_TRUE(v >= 0.0f && v <= 1.0f) << v << " at " << ppd << " pixels per degree";
    }
    EXPECT_EQ(computeFlip(a, a, w, h, ppd).max, 0.0) << ppd << " pixels per degree";
  }
}

TEST(Flip, RejectsMismatchedSizesAndBadViewingDistances) {
  const std::vector<glm::vec3> a = randomImage(4, 4, 13);
  const std::vector<glm::vec3> shorter(15, glm::vec3(0.5f));
  EXPECT_THROW(computeFlip(a, shorter, 4, 4), std::invalid_argument);
  EXPECT_THROW(computeFlip(shorter, a, 4, 4), std::invalid_argument);
  EXPECT_THROW(computeFlip(a, a, 4, 5), std::invalid_argument);
  for (double ppd : {0.0, -67.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                     kMaxPixelsPerDegree * 1.01}) {
    EXPECT_THROW(computeFlip(a, a, 4, 4, ppd), std::invalid_argument) << ppd;
  }
}

TEST(Flip, MapColoursBrightenWithTheError) {
  std::vector<float> ramp(256);
  for (std::size_t i = 0; i < ramp.size(); ++i) ramp[i] = float(i) / 255.0f;
  const std::vector<std::uint8_t> rgba = flipMapRgba8(ramp);
  ASSERT_EQ(rgba.size(), 4 * ramp.size());
  for (std::size_t i = 0; i < ramp.size(); ++i) {
    EXPECT_EQ(rgba[4 * i + 3], 255);
    if (i > 0) {
      for (int c = 0; c < 3; ++c) EXPECT_GE(rgba[4 * i + c], rgba[4 * (i - 1) + c]) << "channel " << c << " at " << i;
      EXPECT_GT(linearLuminance(&rgba[4 * i]), linearLuminance(&rgba[4 * (i - 1)])) << "at " << i;
    }
  }
  EXPECT_LT(linearLuminance(&rgba[0]), 0.01);
  EXPECT_GT(linearLuminance(&rgba[4 * 255]), 0.8);
  // Out of range and NaN are clamped like the inputs.
  const std::vector<float> odd = {-1.0f, std::numeric_limits<float>::quiet_NaN(), 7.0f};
  const std::vector<std::uint8_t> oddRgba = flipMapRgba8(odd);
  EXPECT_TRUE(std::equal(oddRgba.begin(), oddRgba.begin() + 4, rgba.begin()));
  EXPECT_TRUE(std::equal(oddRgba.begin() + 4, oddRgba.begin() + 8, rgba.begin()));
  EXPECT_TRUE(std::equal(oddRgba.begin() + 8, oddRgba.end(), rgba.end() - 4));
}

}  // namespace pbs::test
