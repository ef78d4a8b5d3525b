// What an EmbreeScene holds: the Embree objects (built in embree_build.cpp) and the per-instance
// data that render (embree_render.cpp) shades hits with.
#pragma once

#include "embree_handles.hpp"
#include "embree_shading.hpp"
#include "pbs/scene/embree_caster.hpp"
#include "pbs/scene/scene_draws.hpp"

#include <vector>

namespace pbs {

struct EmbreeScene::Impl {
  SceneMaterials materials;  // points into the Scene's textures
  glm::dvec3 origin{0.0};    // Embree's frame is world − origin
  // Declared in creation order so they are released in reverse: instances, meshes, then the device.
  EmbreeDevice device;
  std::vector<EmbreeSceneHandle> meshScenes;  // by mesh index; null for meshes no node draws
  EmbreeSceneHandle top;
  std::vector<ShadedInstance> instances;  // by the top-level scene's geometry id
};

}  // namespace pbs
