// A scene opened for drawing frames, with what its frames read on demand: the .surfels file through the
// surfel cache and, where the file allows, the glTF's meshes as frames draw them. Shared by `pbs render`
// and `pbs view`, so both open a scene the same way and see the same images.
#pragma once

#include "scene_report.hpp"

#include <pbs/scene/lazy_meshes.hpp>
#include <pbs/surfels/surfel_cache.hpp>

#include <cstdint>
#include <optional>
#include <string>

namespace pbs::cli {

struct FrameSceneOptions {
  std::string scene;                         // a .gltf/.glb file or a built-in name
  std::string surfels;                       // its .surfels file; empty: none
  std::uint64_t cacheBytes = 1024ull << 20;  // each of the surfel cache and the meshes read on demand
  bool meshesOnDemand = true;                // false: the meshes are read whole even where the file allows
  bool rays = false;                         // the frames cast rays at the whole scene (its fit counts the BVH)
  std::uint64_t alongside = 0;               // bytes the frames need besides the scene and the caches (buffers)
  std::string what;                          // what those bytes are for, in a refusal ("rendering 1920x1080")
  std::uint64_t maxMemory = 0;               // --max-memory; 0: the machine's
};

// Not movable: the caches refer to the scene they belong to.
class FrameScene {
 public:
  // Refuses (std::runtime_error) what would not fit in memory before reading it.
  explicit FrameScene(const FrameSceneOptions& options);
  FrameScene(const FrameScene&) = delete;
  FrameScene& operator=(const FrameScene&) = delete;

  LoadedScene loaded;
  std::optional<LazyMeshes> meshes;    // set when the meshes are read as frames draw them
  std::optional<SurfelCache> surfels;  // set with a .surfels file
  std::uint64_t foreseenBytes = 0;     // `alongside` plus the caches' budgets
  std::uint64_t cacheBytes = 0;        // each cache's budget (FrameSceneOptions::cacheBytes)
};

}  // namespace pbs::cli
