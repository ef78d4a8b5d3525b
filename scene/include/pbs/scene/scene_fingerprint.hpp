// A 64-bit fingerprint of everything in a scene that shapes its surfels, so a .surfels file can tell
// the scene it was made from apart from any other.
#pragma once

#include "pbs/scene/scene.hpp"

#include <cstdint>

namespace pbs {

// Hashes the node graph (roots, children, mesh references, the exact bits of every transform), every
// mesh's vertex data, indices and parts, the materials and the textures' pixels. Names do not count.
// Equal scenes give equal values on every machine; any change to what is hashed changes it (up to
// 64-bit collisions).
std::uint64_t sceneFingerprint(const Scene& scene);

}  // namespace pbs
