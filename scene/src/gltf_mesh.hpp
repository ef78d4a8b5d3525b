// Private to the glTF importer: one glTF mesh, its triangle primitives merged into one pbs Mesh.
#pragma once

#include "gltf_accessor.hpp"
#include "gltf_document.hpp"
#include "gltf_material.hpp"
#include "pbs/scene/scene.hpp"

#include <tiny_gltf.h>

#include <array>
#include <functional>
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

// The scene material of a primitive's glTF material (MaterialImport::use, or a table of what it chose).
using MaterialOf = std::function<std::uint32_t(int material, std::string_view referrer)>;

// glTF mesh `mesh` with its TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN primitives as triangle-list
// MeshParts over one vertex array. Normals are computed where the file has none (or a zero one); uvs
// are (0,0) for primitives without TEXCOORD_0 when others have it. With no triangles at all the
// result is an empty Mesh. Zero-filled accessors spend from `zeros`, the import's budget.
Mesh importMesh(const Document& model, int mesh, std::string_view file, const MaterialOf& materialOf,
                SkippedPrimitives& skipped, ZeroFilledBudget& zeros);

// The same mesh without reading an accessor's data: its name and the parts importMesh would give it
// (from the accessors' counts), asking `materialOf` for the same materials in the same order, and no
// arrays (Mesh::loaded() is false; no parts: no triangles). Checks what the parts depend on (modes,
// POSITION, the counted accessor, TRIANGLES counts); importMesh checks the rest when it reads.
Mesh describeMesh(const Document& model, int mesh, std::string_view file, const MaterialOf& materialOf,
                  SkippedPrimitives& skipped);

// The bytes of the buffer views importMesh reads for mesh `mesh` (of a mesh it imported: every reference
// is checked), so that a reader can let them go once the mesh is decoded.
std::vector<std::span<const std::uint8_t>> meshViewBytes(const Document& model, int mesh);

}  // namespace pbs::gltf
