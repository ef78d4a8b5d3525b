// What an EmbreeScene holds: every mesh BVH its nodes need (embree_meshes.hpp) and the top level over
// its instances (embree_instances.hpp).
#pragma once

#include "embree_instances.hpp"
#include "embree_meshes.hpp"
#include "pbs/scene/embree_caster.hpp"
#include "pbs/scene/scene_draws.hpp"

namespace pbs {

struct EmbreeScene::Impl {
  SceneMaterials materials;  // points into the Scene's textures
  // Declared in creation order so they are released in reverse: instances, meshes, then the device.
  EmbreeMeshes meshes;
  EmbreeInstances instances;
};

}  // namespace pbs
