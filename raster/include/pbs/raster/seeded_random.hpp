// The one seeded random generator of pbs (procedural scenes, orderings, benchmarks), with its own
// mappings to numbers: std::*_distribution is implementation-defined, and pbs's outputs must be
// bit-identical on every compiler and standard library.
#pragma once

#include <cstdint>

namespace pbs {

// SplitMix64 (Steele, Lea and Flood 2014): one add and three mixes per draw, every seed usable.
class SeededRandom {
 public:
  explicit SeededRandom(std::uint64_t seed) : state_(seed) {}

  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

  // In [0, 1), from the top 53 bits, so every value is exactly representable.
  double unit() { return double(next() >> 11) * 0x1.0p-53; }

  double range(double lo, double hi) { return lo + (hi - lo) * unit(); }

  // In [0, n) for n > 0, by multiply-shift: no rejection loop, bias below 2^-32 for n < 2^32.
  std::uint64_t below(std::uint64_t n) { return std::uint64_t((static_cast<unsigned __int128>(next()) * n) >> 64); }

  bool chance(double probability) { return unit() < probability; }

 private:
  std::uint64_t state_;
};

}  // namespace pbs
