// `pbs bench order`: the three progressive orderings timed and measured on points on a unit sphere.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>

namespace pbs::bench {

// Orders `max` of `points` seeded uniform points on the unit sphere with orderFarthest, orderDart
// (200 candidates) and orderRandom, each once on one thread; reports seconds and ρ (min, mean, A = 4π).
nlohmann::json benchOrder(std::uint64_t points = 1'000'000, std::uint32_t max = 100'000, std::uint64_t seed = 1);

}  // namespace pbs::bench
