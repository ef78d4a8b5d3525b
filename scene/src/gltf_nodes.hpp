// Private to the glTF importer: the node hierarchy of the scene to import, with node transforms.
#pragma once

#include "pbs/scene/scene.hpp"

#include <tiny_gltf.h>

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace pbs::gltf {

// Picks the default scene, else scene 0, else (no scenes: a warning) every node without a parent as
// a root, and appends the nodes it reaches to scene.nodes in depth-first order, roots to
// scene.roots; unreachable nodes are left out. `meshFor(gltfMesh)` gives the scene mesh of a node's
// glTF mesh (-1: none). Throws InputError naming the node (or scene) for a reference out of range, a
// node reached twice (two parents, a cycle) or a transform that is malformed or not finite.
void importNodes(const tinygltf::Model& model, std::string_view file,
                 const std::function<std::int32_t(int gltfMesh)>& meshFor, Scene& scene,
                 std::vector<std::string>& warnings);

}  // namespace pbs::gltf
