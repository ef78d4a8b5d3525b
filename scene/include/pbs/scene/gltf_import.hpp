// glTF 2.0 import (.gltf with external or embedded files, and .glb) into the scene model.
#pragma once

#include "pbs/scene/scene.hpp"

#include <cstdint>
#include <filesystem>
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

}  // namespace pbs
