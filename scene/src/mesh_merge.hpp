// Bakes transformed meshes into one mesh: how a prototype is flattened for the city and how
// multi-material parts (a valve, a pump) are assembled for the plant.
#pragma once

#include "pbs/scene/scene.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <string>

namespace pbs {

struct MeshPiece {
  const Mesh* mesh = nullptr;
  glm::dmat4 transform{1.0};         // into the merged mesh's frame
  std::uint32_t materialOffset = 0;  // added to each part's material
};

// One mesh holding every piece: positions transformed, normals by the inverse transpose and
// renormalised, winding reversed for mirroring transforms so faces stay counter-clockwise, uvs
// kept (zero where a piece has none while others do) and one part per material, in material
// order. Throws std::length_error when the vertices exceed 32-bit indices.
Mesh mergeMeshes(std::span<const MeshPiece> pieces, std::string name);

}  // namespace pbs
