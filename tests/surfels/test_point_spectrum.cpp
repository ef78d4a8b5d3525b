// The flat-patch spectrum: a lattice's periodogram has power only at its reciprocal lattice, white noise
// is flat, farthest-point order is blue.
#include <pbs/surfels/ordering.hpp>
#include <pbs/surfels/point_spectrum.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace pbs {
namespace {

PointOrdering byName(SurfelOrdering ordering) {
  return [ordering](std::span<const glm::vec3> points, std::uint32_t max, std::uint64_t seed) {
    return orderPoints(ordering, points, max, seed);
  };
}

TEST(Periodogram, LatticeHasPowerOnlyAtItsReciprocalLattice) {
  constexpr int m = 8;
  std::vector<glm::vec2> points;
  for (int y = 0; y < m; ++y)
    for (int x = 0; x < m; ++x) points.emplace_back((x + 0.5f) / m, (y + 0.5f) / m);
  constexpr std::uint32_t F = 20;
  const std::vector<double> p = periodogram(points, F);
  ASSERT_EQ(p.size(), (2 * F + 1) * (2 * F + 1));
  for (int fy = -int(F); fy <= int(F); ++fy) {
    for (int fx = -int(F); fx <= int(F); ++fx) {
      const double expected = (fx % m == 0 && fy % m == 0) ? double(m * m) : 0.0;
      EXPECT_NEAR(p[std::size_t(fy + int(F)) * (2 * F + 1) + std::size_t(fx + int(F))], expected, 1e-6)
          << fx << "," << fy;
    }
  }
  // A single point has power 1 everywhere.
  const glm::vec2 one[] = {{0.3f, 0.7f}};
  for (double v : periodogram(one, 5)) EXPECT_NEAR(v, 1.0, 1e-12);
}

TEST(FlatSpectrum, RandomIsFlatAndFarthestIsBlue) {
  FlatSpectrumOptions options;
  options.candidates = 20000;
  options.count = 256;
  options.realizations = 8;
  const FlatSpectrum random = flatPatchSpectrum(byName(SurfelOrdering::Random), options);
  const FlatSpectrum farthest = flatPatchSpectrum(byName(SurfelOrdering::Farthest), options);
  const FlatSpectrum dart = flatPatchSpectrum(byName(SurfelOrdering::Dart), options);
  ASSERT_EQ(random.maxFrequency, 64u);  // 4·sqrt(256)
  ASSERT_EQ(random.radial.power.size(), 64u);
  EXPECT_NEAR(random.count, 256.0, 20.0);  // the points inside the measured window, on average

  // White noise: expected power 1 at every f ≠ 0; the annuli from r = 4 average ≥ ~100 values.
  double sum = 0.0;
  for (std::size_t i = 0; i < random.radial.power.size(); ++i) {
    if (random.radial.frequency[i] >= 4) {
      EXPECT_NEAR(random.radial.power[i], 1.0, 0.45) << "r " << i + 1;
    }
    sum += random.radial.power[i];
  }
  EXPECT_NEAR(sum / double(random.radial.power.size()), 1.0, 0.08);
  EXPECT_NEAR(random.lowFrequencyPower, 1.0, 0.35);

  // Blue noise: little power below the mean spacing's frequency (sqrt(n) = 16), ≈ 1 far above it.
  EXPECT_LT(farthest.lowFrequencyPower, 0.25);
  EXPECT_LT(dart.lowFrequencyPower, 0.5);
  for (std::size_t r = 1; r <= 8; ++r) EXPECT_LT(farthest.radial.power[r - 1], 0.5) << "r " << r;
  double high = 0.0;
  for (std::size_t r = 48; r <= 64; ++r) high += farthest.radial.power[r - 1] / 17.0;
  EXPECT_NEAR(high, 1.0, 0.25);

  for (const FlatSpectrum* s : {&random, &farthest, &dart})
    for (double a : s->radial.anisotropy) {
      EXPECT_TRUE(std::isfinite(a));
      EXPECT_LT(a, 10.0);
    }
  // Averaging 8 white-noise periodograms: variance / mean² ≈ 1/8, about -9 dB, away from the axes' bias.
  double anisotropy = 0.0;
  for (std::size_t r = 16; r <= 64; ++r) anisotropy += random.radial.anisotropy[r - 1] / 49.0;
  EXPECT_NEAR(anisotropy, -9.0, 1.5);
}

TEST(FlatSpectrum, RejectsBadOptions) {
  FlatSpectrumOptions options;
  options.candidates = 10;
  options.count = 20;
  EXPECT_THROW(flatPatchSpectrum(byName(SurfelOrdering::Random), options), std::invalid_argument);
  options.count = 0;
  EXPECT_THROW(flatPatchSpectrum(byName(SurfelOrdering::Random), options), std::invalid_argument);
}

}  // namespace
}  // namespace pbs
