// Private to the glTF importer: one glTF mesh, its triangle primitives merged into one pbs Mesh.
#pragma once

#include "gltf_accessor.hpp"
#include "gltf_document.hpp"
#include "gltf_material.hpp"
#include "pbs/scene/scene.hpp"

#include <tiny_gltf.h>

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace pbs::gltf {

// Point and line primitives have nothing to draw as triangles: they are counted, per mode, and skipped.
struct SkippedPrimitives {
  std::array<std::uint64_t, 4> byMode{};  // POINTS, LINES, LINE_LOOP, LINE_STRIP

  // One line per mode that had any, e.g. "skipped 3 primitives of mode LINES".
  void appendWarnings(std::vector<std::string>& warnings) const;
};

// glTF mesh `mesh` with its TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN primitives as triangle-list
// MeshParts over one vertex array. Normals are computed where the file has none (or a zero one); uvs
// are (0,0) for primitives without TEXCOORD_0 when others have it. With no triangles at all the
// result is an empty Mesh. Zero-filled accessors spend from `zeros`, the import's budget.
Mesh importMesh(const Document& model, int mesh, std::string_view file, MaterialImport& materials,
                SkippedPrimitives& skipped, ZeroFilledBudget& zeros);

}  // namespace pbs::gltf
