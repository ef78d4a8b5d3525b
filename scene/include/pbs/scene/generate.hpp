// Procedural scenes: the embedded default (an industrial plant of pipes, tanks, gears, lattices
// and tori), a city of instances of given meshes, deep enough to reach billions of triangles, and a
// terrain: one flat mesh of any size under one node, the case with no hierarchy of its own.
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
  // Nothing shared: every leaf gets its own copy of its prototype's mesh with the leaf's local
  // transform baked into the vertices (normals by the inverse transpose, renormalised; winding
  // reversed where it mirrors) and an identity local transform. The same nodes, draws and picture
  // as without (up to float rounding of the vertices), but as many meshes as leaves.
  bool unique = false;
};

// Instances of `prototypes` (each flattened into one mesh, transforms baked) placed over a
// hierarchy of `levels` levels with `fanout` children each, with rotations, non-uniform and
// mirroring scales. Leaves: fanout^levels instances. With options.unique the leaves' meshes are
// baked in parallel, one per leaf in node order (the prototypes' own meshes are not kept).
Scene generateCity(const std::vector<Scene>& prototypes, const CityOptions& options);

// generateCity with options.unique, its meshes not baked yet: the nodes (each leaf's transform the
// identity), materials, textures and every mesh's name and parts (Mesh::loaded() false); `bake(m)` makes
// mesh m as generateCity does, from any thread. So a city larger than memory can be written one mesh at a
// time (writeGltf). options.unique itself is not read.
struct UnbakedCity {
  Scene scene;
  MeshReader bake;
};
UnbakedCity generateUniqueCity(const std::vector<Scene>& prototypes, const CityOptions& options);

struct TerrainOptions {
  std::uint64_t triangles = 1000000;  // at least this many (a square grid: 2·n² for the least such n)
  double size = 1000.0;               // the grid's side, in scene units
  std::uint64_t seed = 1;
};

// A displaced grid: one mesh of one material under one node, heights a sum of a few seeded sine waves
// of falling wavelength and amplitude (rolling hills with small ridges), normals from the triangles. Deterministic for
// any thread count. Throws std::invalid_argument for 0 triangles or more than a 32-bit index can address.
Scene generateTerrain(const TerrainOptions& options);

}  // namespace pbs
