// Loads what a command line names as SCENE: a .gltf/.glb file, or `default` for the embedded scene.
#pragma once

#include "pbs/scene/gltf_import.hpp"

#include <cstdint>
#include <string>

namespace pbs {

struct LoadOptions {
  std::uint32_t octreeLeafTriangles = 0;  // 0: keep the file's hierarchy; N: loose octree, N per leaf
};

// Loads, validates (InputError on any problem, including a scene with nothing to draw) and
// optionally rebuilds as a loose octree.
ImportResult loadScene(const std::string& spec, const LoadOptions& options = {});

}  // namespace pbs
