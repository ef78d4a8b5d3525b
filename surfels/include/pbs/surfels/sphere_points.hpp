// Seeded points uniform on the unit sphere: the reference input of the ordering benchmark and tests.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace pbs {

// z uniform in [−1, 1] and an independent uniform angle (Archimedes), from a SeededRandom: the same
// points on every compiler and standard library.
std::vector<glm::vec3> uniformSpherePoints(std::uint64_t count, std::uint64_t seed);

}  // namespace pbs
