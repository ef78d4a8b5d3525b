// subtreeClasses: bottom-up canonical numbering of subtrees by their exact contents.
#include "pbs/scene/subtree_classes.hpp"

#include <bit>
#include <map>

namespace pbs {

std::vector<std::uint32_t> subtreeClasses(const Scene& scene, const Hierarchy& hierarchy) {
  constexpr std::uint32_t kUnset = 0xffffffffu;
  // Children before parents: a node's key holds its children's (provisional) classes.
  std::vector<std::uint32_t> provisional(scene.nodes.size(), kUnset);
  std::map<std::vector<std::uint64_t>, std::uint32_t> classOfKey;
  std::vector<std::uint64_t> key;
  for (auto it = hierarchy.preorder.rbegin(); it != hierarchy.preorder.rend(); ++it) {
    const Node& node = scene.nodes[*it];
    key.assign({std::uint64_t(std::int64_t(node.mesh)), node.children.size()});
    for (std::uint32_t child : node.children) {
      const glm::dmat4& local = scene.nodes[child].local;
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) key.push_back(std::bit_cast<std::uint64_t>(local[c][r]));
      key.push_back(provisional[child]);
    }
    provisional[*it] = classOfKey.try_emplace(key, std::uint32_t(classOfKey.size())).first->second;
  }
  // Renumber by first appearance in preorder, so numbers do not depend on the map's internals.
  std::vector<std::uint32_t> renumbered(classOfKey.size(), kUnset);
  std::vector<std::uint32_t> classes(scene.nodes.size(), kUnset);
  std::uint32_t next = 0;
  for (std::uint32_t n : hierarchy.preorder) {
    std::uint32_t& number = renumbered[provisional[n]];
    if (number == kUnset) number = next++;
    classes[n] = number;
  }
  return classes;
}

}  // namespace pbs
