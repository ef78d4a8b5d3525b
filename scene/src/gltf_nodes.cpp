// glTF nodes to the scene's hierarchy: scene choice, an iterative depth-first walk (files may be
// deeper than the call stack) that rejects shared and cyclic nodes, and node transforms.
#include "gltf_nodes.hpp"

#include "gltf_messages.hpp"
#include "pbs/scene/input_error.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>

namespace pbs::gltf {
namespace {

constexpr int kUnreached = -2;  // in reachedFrom: not reached yet
constexpr int kRoot = -1;       // in reachedFrom: reached as a scene root

void checkNumbers(const std::vector<double>& values, std::size_t count, const char* what, std::string_view file,
                  int node) {
  if (!values.empty() && values.size() != count) {
    throw InputError(
        file, elementName("node", node),
        std::string(what) + " has " + std::to_string(values.size()) + " numbers, not " + std::to_string(count));
  }
  if (!std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); })) {
    throw InputError(file, elementName("node", node), std::string(what) + " is not finite");
  }
}

// `matrix` (column-major, as glm stores it) or translation * rotation * scale.
glm::dmat4 localTransform(const tinygltf::Node& node, int index, std::string_view file) {
  if (!node.matrix.empty()) {
    checkNumbers(node.matrix, 16, "matrix", file, index);
    glm::dmat4 m;
    for (std::size_t i = 0; i < 16; ++i) m[static_cast<int>(i / 4)][static_cast<int>(i % 4)] = node.matrix[i];
    return m;
  }
  checkNumbers(node.translation, 3, "translation", file, index);
  checkNumbers(node.rotation, 4, "rotation", file, index);
  checkNumbers(node.scale, 3, "scale", file, index);
  glm::dmat4 m(1.0);
  if (!node.translation.empty())
    m = glm::translate(m, glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
  if (!node.rotation.empty()) {
    glm::dvec4 q(node.rotation[0], node.rotation[1], node.rotation[2], node.rotation[3]);  // x, y, z, w
    const double largest = std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z), std::abs(q.w)});
    if (largest == 0.0) throw InputError(file, elementName("node", index), "rotation quaternion is zero");
    q = glm::normalize(q / largest);  // scaled first, so that huge components do not overflow when squared
    m *= glm::mat4_cast(glm::dquat(q.w, q.x, q.y, q.z));
  }
  if (!node.scale.empty()) m = glm::scale(m, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
  return m;
}

std::vector<int> chooseRoots(const tinygltf::Model& model, std::string_view file, std::vector<std::string>& warnings) {
  const std::size_t nodeCount = model.nodes.size();
  if (model.scenes.empty()) {
    std::vector<bool> hasParent(nodeCount, false);
    for (std::size_t n = 0; n < nodeCount; ++n) {
      for (const int child : model.nodes[n].children) {
        if (!validIndex(child, nodeCount)) {
          throw InputError(file, elementName("node", static_cast<std::int64_t>(n)),
                           "child " + missingElement("node", child, nodeCount));
        }
        hasParent[static_cast<std::size_t>(child)] = true;
      }
    }
    std::vector<int> roots;
    for (std::size_t n = 0; n < nodeCount; ++n)
      if (!hasParent[n]) roots.push_back(static_cast<int>(n));
    if (nodeCount > 0) {
      warnings.push_back("the file has no scenes: its " + std::to_string(roots.size()) +
                         " nodes without a parent are the roots");
    }
    return roots;
  }
  int chosen = model.defaultScene;
  if (chosen == -1) {
    chosen = 0;  // tinygltf's "no default scene"
  } else if (!validIndex(chosen, model.scenes.size())) {
    throw InputError(file, "scene", "the default " + missingElement("scene", chosen, model.scenes.size()));
  }
  const std::vector<int>& roots = model.scenes[static_cast<std::size_t>(chosen)].nodes;
  for (const int root : roots) {
    if (!validIndex(root, nodeCount))
      throw InputError(file, elementName("scene", chosen), missingElement("node", root, nodeCount));
  }
  return roots;
}

// A node reached a second time is either in a cycle (it is an ancestor of the node that reaches it
// again) or has two parents (counting "scene root" as one).
[[noreturn]] void throwReachedTwice(const std::vector<int>& reachedFrom, int node, int parent, std::string_view file) {
  const std::string element = elementName("node", node);
  for (int ancestor = parent; ancestor >= 0; ancestor = reachedFrom[static_cast<std::size_t>(ancestor)]) {
    if (ancestor == node) {
      throw InputError(file, element,
                       "is in a cycle (it is a descendant of itself, through node " + std::to_string(parent) + ")");
    }
  }
  const int first = reachedFrom[static_cast<std::size_t>(node)];
  if (first == kRoot && parent == kRoot) throw InputError(file, element, "is listed twice among the scene's roots");
  const auto describe = [](int from) {
    return from == kRoot ? std::string("a scene root") : "a child of node " + std::to_string(from);
  };
  throw InputError(file, element, "has two parents: it is " + describe(first) + " and " + describe(parent));
}

}  // namespace

void importNodes(const tinygltf::Model& model, std::string_view file,
                 const std::function<std::int32_t(int gltfMesh)>& meshFor, Scene& scene,
                 std::vector<std::string>& warnings) {
  const std::size_t nodeCount = model.nodes.size();
  const std::vector<int> roots = chooseRoots(model, file, warnings);
  std::vector<int> reachedFrom(nodeCount, kUnreached);  // glTF node to the glTF node it was reached from
  std::vector<std::uint32_t> sceneIndex(nodeCount, 0);  // glTF node to scene node, once visited
  std::vector<int> stack;
  const auto reach = [&](int node, int from) {
    if (reachedFrom[static_cast<std::size_t>(node)] != kUnreached) throwReachedTwice(reachedFrom, node, from, file);
    reachedFrom[static_cast<std::size_t>(node)] = from;
  };

  for (const int root : roots) {
    reach(root, kRoot);
    stack.push_back(root);
    while (!stack.empty()) {
      const int n = stack.back();
      stack.pop_back();
      const tinygltf::Node& source = model.nodes[static_cast<std::size_t>(n)];
      Node node;
      node.name = source.name;
      node.local = localTransform(source, n, file);
      if (source.mesh != -1) {
        if (!validIndex(source.mesh, model.meshes.size())) {
          throw InputError(file, elementName("node", n), missingElement("mesh", source.mesh, model.meshes.size()));
        }
        node.mesh = meshFor(source.mesh);
      }
      for (const int child : source.children) {
        if (!validIndex(child, nodeCount)) {
          throw InputError(file, elementName("node", n), "child " + missingElement("node", child, nodeCount));
        }
        reach(child, n);
      }
      // Reversed, so that the first child is visited next: depth-first order with children in file order.
      stack.insert(stack.end(), source.children.rbegin(), source.children.rend());

      const auto index = static_cast<std::uint32_t>(scene.nodes.size());
      sceneIndex[static_cast<std::size_t>(n)] = index;
      const int parent = reachedFrom[static_cast<std::size_t>(n)];
      if (parent == kRoot) {
        scene.roots.push_back(index);
      } else {
        scene.nodes[sceneIndex[static_cast<std::size_t>(parent)]].children.push_back(index);
      }
      scene.nodes.push_back(std::move(node));
    }
  }
}

}  // namespace pbs::gltf
