// Writes a scene as glTF, whole or not at all: one binary .glb, or a .gltf with its data in .bin files.
#pragma once

#include "pbs/scene/scene.hpp"

#include <cstdint>
#include <filesystem>
#include <vector>

namespace pbs {

// Writes to a temporary name beside `file` and renames it into place, so a reader never sees a
// half-written file. Textures are stored as embedded PNG. Throws std::runtime_error on I/O failure.
void writeGlb(const Scene& scene, const std::filesystem::path& file);

// The same as a .gltf `file` with its binary data in files beside it, `<file's stem>.<k>.bin`, each at
// most `maxBinBytes` unless one array is larger (no 4 GiB limit as in a .glb), written as the meshes come: mesh m is
// read by `meshAt(m)`, in order, one at a time, so a scene larger than memory (its meshes described, not loaded) can be
// written as it is made. The .bin files go into place before the .gltf that names them. Returns the files
// written, the .gltf first.
std::vector<std::filesystem::path> writeGltf(const Scene& scene, const MeshReader& meshAt,
                                             const std::filesystem::path& file,
                                             std::uint64_t maxBinBytes = std::uint64_t(1) << 30);

}  // namespace pbs
