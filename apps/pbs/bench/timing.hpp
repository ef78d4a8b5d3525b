// Timing helpers for the benchmarks: contenders timed in interleaved rounds so that they meet the
// same machine noise, medians, and ratios round by round.
#pragma once

#include <pbs/evaluation/report_numbers.hpp>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <functional>
#include <span>
#include <vector>

namespace pbs::bench {

// How every benchmark report's timings were taken, for its "timing" entry.
inline constexpr const char* kInterleavedTiming =
    "interleaved rounds: medians of each contender's seconds, ratios as medians of per-round ratios";

// Seconds of one run of `work`, timed whole.
template <typename Work>
double timedRun(Work&& work) {
  const auto start = std::chrono::steady_clock::now();
  work();
  return secondsSince(start);
}

// Contenders timed against each other: each runs once to warm up, then `repeats` rounds in which
// every contender runs once in turn. A busy neighbour on a shared machine then slows one round of
// every contender, not every run of one of them, and a ratio taken round by round cancels it.
// Each run returns its own seconds (so that it can leave checks out of its time); the result holds
// them per contender, in round order.
inline std::vector<std::vector<double>> interleavedRounds(std::span<const std::function<double()>> runs, int repeats) {
  for (const auto& run : runs) run();
  std::vector<std::vector<double>> seconds(runs.size());
  for (int r = 0; r < std::max(1, repeats); ++r)
    for (std::size_t c = 0; c < runs.size(); ++c) seconds[c].push_back(runs[c]());
  return seconds;
}

// The median over rounds of slow[r] / fast[r]: how many times faster `fast` was, round by round.
inline double medianRatio(const std::vector<double>& slow, const std::vector<double>& fast) {
  std::vector<double> ratios;
  for (std::size_t r = 0; r < std::min(slow.size(), fast.size()); ++r)
    if (fast[r] > 0.0) ratios.push_back(slow[r] / fast[r]);
  return median(std::move(ratios));
}

}  // namespace pbs::bench
