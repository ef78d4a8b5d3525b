// Wall time of a stage, for the LodStats of the renderers.
#pragma once

#include <chrono>

namespace pbs::detail {

using Clock = std::chrono::steady_clock;

inline double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace pbs::detail
