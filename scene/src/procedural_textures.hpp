// Procedural, seamlessly tiling 256×256 textures for the generated plant: painted steel with
// rust, checker plate, hazard stripes and concrete. Deterministic for a given seed.
#pragma once

#include "pbs/scene/scene.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <string>

namespace pbs {

// Paint in `paint` (sRGB, 0..1) with a band of `stripe` across the middle rows, worn to rust in
// patches.
Texture makePaintedSteelTexture(std::string name, glm::vec3 paint, glm::vec3 stripe, std::uint32_t seed);

// Steel floor plate with raised diamond lugs.
Texture makeCheckerPlateTexture(std::string name, std::uint32_t seed);

// Diagonal yellow and black warning stripes, scuffed.
Texture makeHazardStripeTexture(std::string name, std::uint32_t seed);

// Weathered concrete with formwork joints.
Texture makeConcreteTexture(std::string name, std::uint32_t seed);

}  // namespace pbs
