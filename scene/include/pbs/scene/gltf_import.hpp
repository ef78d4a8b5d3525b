// glTF 2.0 import (.gltf with external or embedded files, and .glb) into the scene model.
#pragma once

#include "pbs/scene/scene.hpp"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace pbs {

struct ImportResult {
  Scene scene;
  std::vector<std::string> warnings;  // one line each, e.g. "skipped 3 primitives of mode LINES"
};

// Reads the file's default scene (else scene 0). Throws InputError naming the file and the
// element (accessor 3, node 12, …) for anything malformed; never reads out of bounds.
ImportResult importGltf(const std::filesystem::path& file);

// The same from bytes in memory; `name` stands for the file in messages and `baseDir` resolves
// relative URIs (external buffers and images).
ImportResult importGltfFromMemory(std::span<const std::uint8_t> bytes, const std::string& name,
                                  const std::filesystem::path& baseDir);

// A scene opened without its mesh arrays, and what reads them (for LazyMeshes).
struct LazyGltf {
  ImportResult imported;                           // every mesh with its name and parts only (Mesh::loaded() false)
  std::function<Mesh(std::uint32_t mesh)> decode;  // mesh `mesh`'s arrays, as importGltf gives them
  std::uint64_t bufferBytes = 0;                   // of the file's buffers: what reading every mesh at once maps
};

// importGltf's scene without reading any accessor's data (the counts that give each mesh's parts come
// from the JSON): the file stays mapped for `decode`, which reads one mesh at a time, from any thread.
// Errors in the structure are thrown here; errors in a mesh's data when `decode` reads it. Importing the
// same file whole gives the same scene once every mesh is decoded; only the budget for zero-filled
// accessors is per mesh here instead of per file.
LazyGltf openGltfWithoutMeshes(const std::filesystem::path& file);

}  // namespace pbs
