// The default plant's unique meshes, with their materials and textures: added to a scene once,
// then instanced many times by the layout in generate_default.cpp.
#pragma once

#include "pbs/scene/scene.hpp"

#include <cstdint>

namespace pbs {

// Mesh indices into Scene::meshes. Parts stand on the origin and rise along +Y unless noted.
struct PlantCatalog {
  std::int32_t storageTank;   // dished-head tank, radius 11 m
  std::int32_t sphere;        // spherical gas holder, radius 8 m, bottom at the origin
  std::int32_t column;        // process column, radius 1.6 m
  std::int32_t columnSkirt;   // concrete support under a column
  std::int32_t tankRing;      // stiffener ring for the storage tank (major radius 11.15 m)
  std::int32_t platformRing;  // walkway ring around a column (major radius 2.2 m)
  std::int32_t flange;        // ring for a 0.3 m pipe
  std::int32_t pipeGrey;      // straight pipe, radius 0.3 m, 1 m long: scale y for length
  std::int32_t pipeBlue;
  std::int32_t elbow;          // 90° bend from +Y to +X, radius 0.3 m
  std::int32_t expansionLoop;  // 8 m run along +X rising 3 m in a loop
  std::int32_t riser;          // tank outlet: out along +Z, then up
  std::int32_t gearLarge;      // 48 teeth, pitch radius about 0.96 m
  std::int32_t gearSmall;      // 16 teeth, pitch radius about 0.31 m
  std::int32_t shaft;          // radius 0.08 m, 1 m long
  std::int32_t concreteBlock;  // unit box: scale to size
  std::int32_t tankPad;        // 30 × 0.6 × 30 m concrete pad
  std::int32_t tankPlinth;     // concrete ring wall the storage tank stands in, 2.4 m tall
  std::int32_t processSkid;    // 44 × 0.4 × 34 m steel deck in checker plate
  std::int32_t housing;        // unit box, machine green
  std::int32_t stairTower;     // 3 m square lattice, 14 m tall
  std::int32_t rackTruss;      // 2.5 m square lattice, 8 m long, along +Y: turn it to lie flat
  std::int32_t pylon;          // 45 m transmission tower with two cross-arms
  std::int32_t valve;          // body, stem and red handwheel, 1.5 m tall
  std::int32_t pump;           // skid, motor and volute
  std::int32_t coolingTower;   // hyperboloid shell, 110 m tall
  std::int32_t stack;          // tapered chimney, 80 m tall
  std::int32_t turbine;        // casing, radius 2.5 m, 12 m tall: turn it to lie flat
};

PlantCatalog addPlantCatalog(Scene& scene);

}  // namespace pbs
