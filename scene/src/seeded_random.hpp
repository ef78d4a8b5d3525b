// A small seeded generator for the procedural scenes, with its own mappings to numbers: the
// std::*_distribution classes are implementation-defined, and the scenes must be bit-identical
// on every standard library.
#pragma once

#include <cstdint>

namespace pbs {

// SplitMix64 (Steele, Lea and Flood 2014): one add and three mixes per draw, every seed usable.
struct SeededRandom {
  std::uint64_t state;

  explicit SeededRandom(std::uint64_t seed) : state(seed) {}

  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

  // In [0, 1), from the top 53 bits, so every value is exactly representable.
  double unit() { return double(next() >> 11) * 0x1.0p-53; }

  double range(double lo, double hi) { return lo + (hi - lo) * unit(); }

  // In [0, n) for n > 0; the multiply-shift mapping has a negligible bias for small n.
  std::uint32_t below(std::uint32_t n) { return std::uint32_t(((next() >> 32) * std::uint64_t(n)) >> 32); }

  bool chance(double probability) { return unit() < probability; }
};

}  // namespace pbs
