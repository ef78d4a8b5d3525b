// A node named by a user: by its name, or by its index in the scene's node list.
#pragma once

#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/scene.hpp"

#include <cstdint>
#include <string>

namespace pbs {

// The first node in preorder named `wanted`, else the node of that index; the first root when `wanted`
// is empty. Throws InputError naming `source` (the scene's file) when no node matches or the scene has
// no root.
std::uint32_t findNode(const Scene& scene, const Hierarchy& hierarchy, const std::string& wanted,
                       const std::string& source);

}  // namespace pbs
