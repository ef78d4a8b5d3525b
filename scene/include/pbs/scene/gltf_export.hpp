// Writes a scene as one binary glTF (.glb) file, whole or not at all.
#pragma once

#include "pbs/scene/scene.hpp"

#include <filesystem>

namespace pbs {

// Writes to a temporary name beside `file` and renames it into place, so a reader never sees a
// half-written file. Textures are stored as embedded PNG. Throws std::runtime_error on I/O failure.
void writeGlb(const Scene& scene, const std::filesystem::path& file);

}  // namespace pbs
