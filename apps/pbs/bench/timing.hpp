// Timing helpers for the benchmarks: the median of repeated runs of a piece of work.
#pragma once

#include "../report_numbers.hpp"

#include <algorithm>
#include <chrono>
#include <vector>

namespace pbs::bench {

// Runs `work` once to warm caches and allocators, then `repeats` times; returns the median seconds.
template <typename Work>
double medianSeconds(int repeats, Work&& work) {
  work();
  std::vector<double> seconds;
  for (int r = 0; r < std::max(1, repeats); ++r) {
    const auto start = std::chrono::steady_clock::now();
    work();
    seconds.push_back(cli::secondsSince(start));
  }
  std::nth_element(seconds.begin(), seconds.begin() + seconds.size() / 2, seconds.end());
  return seconds[seconds.size() / 2];
}

}  // namespace pbs::bench
