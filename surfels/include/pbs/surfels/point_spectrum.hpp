// Fourier measures of a progressive ordering on a flat patch: the periodogram of its first n points,
// the radially averaged power and the anisotropy (Ulichney's measures of blue noise).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace pbs {

// The periodogram P(f) = |Σ_j exp(-2πi f·x_j)|² / n of points in [0, 1)² at integer frequencies
// f = (fx, fy) with |fx|, |fy| ≤ maxFrequency, row-major by fy then fx, (2F+1)² values; P(0) = n.
// A uniformly random set has expected power 1 at every f ≠ 0; blue noise has little power at low |f|.
// Parallel over rows (TBB); the result does not depend on the thread count.
std::vector<double> periodogram(std::span<const glm::vec2> points, std::uint32_t maxFrequency);

struct RadialSpectrum {
  // Annulus r (r = 1 … maxFrequency) holds the frequencies with round(|f|) = r; entry r-1 describes it.
  std::vector<double> frequency;   // r, in cycles across the unit square
  std::vector<double> power;       // mean of P over the annulus
  std::vector<double> anisotropy;  // 10·log10(variance / mean²) of P over the annulus, in dB
};

// Radial mean and anisotropy of a periodogram laid out as periodogram() returns it.
RadialSpectrum radialSpectrum(std::span<const double> periodogram, std::uint32_t maxFrequency);

// An ordering as ordering.hpp declares them: (points, max, seed) → indices.
using PointOrdering =
    std::function<std::vector<std::uint32_t>(std::span<const glm::vec3> points, std::uint32_t max, std::uint64_t seed)>;

struct FlatSpectrumOptions {
  std::uint32_t candidates = 100'000;  // uniform random candidates per unit square (see below)
  std::uint32_t count = 1024;          // ordered points per unit square: about this many are measured
  std::uint32_t realizations = 8;      // periodograms averaged (seeds seed, seed+1, …)
  std::uint32_t maxFrequency = 0;      // 0: 4·sqrt(count), four times the frequency of the mean spacing
  std::uint64_t seed = 1;
};

struct FlatSpectrum {
  std::uint32_t count = 0;  // points measured per realization, on average
  std::uint32_t maxFrequency = 0;
  RadialSpectrum radial;  // of the averaged periodogram
  // Mean radial power over 1 ≤ r ≤ sqrt(count)/2: ≈ 1 for white noise, well below 1 for blue noise.
  double lowFrequencyPower = 0.0;
};

// Per realization: 4·candidates seeded uniform candidates on the patch [0, 2)² (z = 0), ordered with
// `ordering` up to 4·count points; the ordered points inside the central unit square [0.5, 1.5)² (about
// `count`, away from the patch's edges, which orderings treat differently) are measured. The
// periodograms of `realizations` such sets are averaged. Throws std::invalid_argument for zero
// counts or count > candidates.
FlatSpectrum flatPatchSpectrum(const PointOrdering& ordering, const FlatSpectrumOptions& options);

}  // namespace pbs
