// findNode: names first, then indices, so a node named "12" is found by its name.
#include "pbs/scene/find_node.hpp"

#include "pbs/scene/input_error.hpp"

namespace pbs {

std::uint32_t findNode(const Scene& scene, const Hierarchy& hierarchy, const std::string& wanted,
                       const std::string& source) {
  if (wanted.empty()) {
    if (scene.roots.empty()) throw InputError(source, "", "the scene has no root node");
    return scene.roots.front();
  }
  for (std::uint32_t n : hierarchy.preorder)
    if (scene.nodes[n].name == wanted) return n;
  if (wanted.find_first_not_of("0123456789") == std::string::npos && wanted.size() < 10) {
    const auto index = std::stoul(wanted);
    if (index < scene.nodes.size()) return std::uint32_t(index);
  }
  throw InputError(source, "node " + wanted, "no node has this name or index");
}

}  // namespace pbs
