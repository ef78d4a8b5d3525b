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

// A loaded scene rebuilt as loadScene does with octreeLeafTriangles = `leafTriangles`: the same scene,
// bit for bit, without reading the file again. `source` names it in errors.
Scene asLooseOctree(const Scene& scene, std::uint32_t leafTriangles, const std::string& source);

// The same for a glTF file opened without its mesh arrays (openGltfWithoutMeshes; `default` is not a
// file), validated as far as its structure goes. No octree: it would split the meshes.
LazyGltf loadSceneWithoutMeshes(const std::string& spec);

}  // namespace pbs
