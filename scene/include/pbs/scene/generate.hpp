// Procedural scenes: the embedded default (an industrial plant of pipes, tanks, gears, lattices
// and tori) and a city of instances of given meshes, deep enough to reach billions of triangles.
#pragma once

#include "pbs/scene/scene.hpp"

#include <cstdint>
#include <vector>

namespace pbs {

// The embedded default scene: deterministic, deep hierarchy, instanced, textured and untextured
// materials, tens of millions of instanced triangles.
Scene generateDefaultScene();

struct CityOptions {
  std::uint32_t levels = 4;   // depth of the block hierarchy below the root
  std::uint32_t fanout = 10;  // children per block
  std::uint64_t seed = 1;
};

// Instances of `prototypes` (each flattened into one mesh, transforms baked) placed over a
// hierarchy of `levels` levels with `fanout` children each, with rotations, non-uniform and
// mirroring scales. Leaves: fanout^levels instances.
Scene generateCity(const std::vector<Scene>& prototypes, const CityOptions& options);

}  // namespace pbs
