// Scene validation and the per-node values derived from the hierarchy (world transforms, exact
// world bounds, subtree triangle counts).
#include "pbs/scene/hierarchy.hpp"

#include "pbs/scene/input_error.hpp"

#include "instance_bounds.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>

namespace pbs {
namespace {

std::string element(const char* kind, std::size_t index) { return std::string(kind) + " " + std::to_string(index); }

bool finite(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

template <typename Vec>
bool allFinite(const std::vector<Vec>& values) {
  for (const Vec& v : values)
    for (int i = 0; i < Vec::length(); ++i)
      if (!std::isfinite(v[i])) return false;
  return true;
}

// The parts of a mesh: in order, whole triangles each, materials that exist. All a mesh whose arrays are
// not loaded has; returns the indices they cover.
std::size_t validateParts(const Scene& scene, const Mesh& mesh, const std::string& name, std::string_view source) {
  std::size_t covered = 0;
  for (std::size_t p = 0; p < mesh.parts.size(); ++p) {
    const MeshPart& part = mesh.parts[p];
    const std::string partName = name + " part " + std::to_string(p);
    if (part.firstIndex != covered || part.indexCount % 3 != 0)
      throw InputError(source, partName, "parts must cover the indices in order, whole triangles each");
    if (part.material >= scene.materials.size()) throw InputError(source, partName, "material out of range");
    covered += part.indexCount;
  }
  return covered;
}

void validateMesh(const Scene& scene, std::size_t m, std::string_view source) {
  const Mesh& mesh = scene.meshes[m];
  const std::string name = element("mesh", m);
  if (!mesh.loaded()) {
    validateParts(scene, mesh, name, source);  // the arrays are checked by their fingerprint when read
    return;
  }
  if (!allFinite(mesh.positions)) throw InputError(source, name, "a position is not finite");
  if (mesh.normals.size() != mesh.positions.size())
    throw InputError(source, name, "normal count differs from position count");
  if (!allFinite(mesh.normals)) throw InputError(source, name, "a normal is not finite");
  if (!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size())
    throw InputError(source, name, "uv count differs from position count");
  if (!allFinite(mesh.uvs)) throw InputError(source, name, "a uv is not finite");
  if (mesh.indices.size() % 3 != 0) throw InputError(source, name, "index count is not a multiple of 3");
  for (std::size_t i = 0; i < mesh.indices.size(); ++i)
    if (mesh.indices[i] >= mesh.positions.size())
      throw InputError(source, name,
                       "index " + std::to_string(mesh.indices[i]) + " out of range (" +
                           std::to_string(mesh.positions.size()) + " vertices)");
  if (validateParts(scene, mesh, name, source) != mesh.indices.size())
    throw InputError(source, name, "parts do not cover every index");
}

}  // namespace

void validateScene(const Scene& scene, std::string_view source) {
  for (std::size_t t = 0; t < scene.textures.size(); ++t) {
    const Texture& texture = scene.textures[t];
    if (texture.width == 0 || texture.height == 0 ||
        texture.rgba8.size() != std::size_t(texture.width) * texture.height * 4)
      throw InputError(source, element("texture", t), "pixel data does not match its size");
  }
  for (std::size_t m = 0; m < scene.materials.size(); ++m) {
    const Material& material = scene.materials[m];
    for (int i = 0; i < 4; ++i)
      if (!std::isfinite(material.baseColorFactor[i]))
        throw InputError(source, element("material", m), "base colour factor is not finite");
    if (material.baseColorTexture < -1 || material.baseColorTexture >= std::int64_t(scene.textures.size()))
      throw InputError(source, element("material", m), "base colour texture out of range");
  }
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) validateMesh(scene, m, source);

  // Every node has one parent at most, and every node is reached from a root exactly once: together
  // these rule out cycles (a cycle is never reachable from a root without a second parent).
  const std::size_t count = scene.nodes.size();
  std::vector<std::int64_t> parent(count, -1);
  std::vector<bool> isRoot(count, false);
  for (std::uint32_t root : scene.roots) {
    if (root >= count) throw InputError(source, "scene", "root node " + std::to_string(root) + " does not exist");
    if (isRoot[root]) throw InputError(source, element("node", root), "listed twice as a root");
    isRoot[root] = true;
  }
  for (std::size_t n = 0; n < count; ++n) {
    const Node& node = scene.nodes[n];
    if (!finite(node.local)) throw InputError(source, element("node", n), "transform is not finite");
    if (node.mesh < -1 || node.mesh >= std::int64_t(scene.meshes.size()))
      throw InputError(source, element("node", n), "mesh " + std::to_string(node.mesh) + " does not exist");
    for (std::uint32_t child : node.children) {
      if (child >= count)
        throw InputError(source, element("node", n), "child node " + std::to_string(child) + " does not exist");
      if (isRoot[child] || parent[child] >= 0)
        throw InputError(source, element("node", child), "has two parents (a node graph must be a forest)");
      parent[child] = std::int64_t(n);
    }
  }
  // The walk also checks world transforms: finite local ones can overflow in their product (scale
  // 1e200 under scale 1e200), and every world bound and drawn position below would be Inf. And where
  // a mesh lands: pbs stores and draws in float, so a world coordinate past float's range (a vertex
  // near 3e38 under a scale above 1) would reach the outputs as Inf. Mesh::bounds is every
  // producer's (updateMeshBounds); a mesh without them is not checked here.
  constexpr double kFloatRange = std::numeric_limits<float>::max();
  std::vector<bool> reached(count, false);
  std::vector<std::pair<std::uint32_t, glm::dmat4>> stack;
  for (std::uint32_t root : scene.roots) stack.emplace_back(root, scene.nodes[root].local);
  std::size_t reachedCount = 0;
  while (!stack.empty()) {
    const auto [n, world] = stack.back();
    stack.pop_back();
    if (!finite(world))
      throw InputError(source, element("node", n), "world transform is not finite (the transforms above it overflow)");
    if (const std::int32_t mesh = scene.nodes[n].mesh; mesh >= 0 && !scene.meshes[std::size_t(mesh)].bounds.empty()) {
      const Bounds box = transformCorners(scene.meshes[std::size_t(mesh)].bounds, world);
      if (!(glm::all(glm::lessThanEqual(glm::abs(box.min), glm::dvec3(kFloatRange))) &&
            glm::all(glm::lessThanEqual(glm::abs(box.max), glm::dvec3(kFloatRange)))))
        throw InputError(source, element("node", n), "its mesh reaches past float's range in the world (above 3.4e38)");
    }
    reached[n] = true;
    ++reachedCount;
    for (std::uint32_t child : scene.nodes[n].children) stack.emplace_back(child, world * scene.nodes[child].local);
  }
  if (reachedCount != count) {
    const auto orphan = std::find(reached.begin(), reached.end(), false) - reached.begin();
    throw InputError(source, element("node", std::size_t(orphan)), "is not reachable from a root (part of a cycle?)");
  }
}

namespace {

// The hierarchy below `starts` without its boxes and counts: parents, depths, world transforms and the
// preorder. A start's world transform is its local one, or the identity when `startsInOwnFrame` (then
// everything is seen from the start node's own frame).
Hierarchy walkFrom(const Scene& scene, std::span<const std::uint32_t> starts, bool startsInOwnFrame) {
  const std::size_t count = scene.nodes.size();
  Hierarchy h;
  h.parent.assign(count, -1);
  h.depth.assign(count, 0);
  h.world.assign(count, glm::dmat4(1.0));
  h.worldBounds.assign(count, Bounds{});
  h.instanceBounds.assign(count, Bounds{});
  h.subtreeTriangles.assign(count, 0);
  h.subtreeMeshNodes.assign(count, 0);
  h.preorder.reserve(count);

  std::vector<std::uint32_t> stack(starts.rbegin(), starts.rend());
  while (!stack.empty()) {
    const std::uint32_t n = stack.back();
    stack.pop_back();
    h.preorder.push_back(n);
    const Node& node = scene.nodes[n];
    if (h.parent[n] >= 0)
      h.world[n] = h.world[h.parent[n]] * node.local;
    else if (!startsInOwnFrame)
      h.world[n] = node.local;
    for (auto child = node.children.rbegin(); child != node.children.rend(); ++child) {
      h.parent[*child] = std::int32_t(n);
      h.depth[*child] = h.depth[n] + 1;
      stack.push_back(*child);
    }
  }
  return h;
}

// Exact instance boxes: the tight box of every vertex of every instance through its full world
// transform, found by branch and bound over per-mesh point clusters (built once per mesh, in
// parallel). Each node's box is independent, so the nodes split across threads with no effect on the
// result.
void boundInstances(const Scene& scene, Hierarchy& h) {
  std::vector<std::uint32_t> instances;
  std::vector<char> meshUsed(scene.meshes.size(), 0);
  for (std::uint32_t n : h.preorder) {
    if (scene.nodes[n].mesh < 0) continue;
    instances.push_back(n);
    meshUsed[std::size_t(scene.nodes[n].mesh)] = 1;
  }
  std::vector<detail::ClusteredPoints> clustered(scene.meshes.size());
  tbb::parallel_for(std::size_t(0), scene.meshes.size(), [&](std::size_t m) {
    if (meshUsed[m]) clustered[m] = detail::clusterPoints(scene.meshes[m].positions);
  });
  tbb::parallel_for(std::size_t(0), instances.size(), [&](std::size_t i) {
    const std::uint32_t n = instances[i];
    h.instanceBounds[n] = detail::transformedPointBounds(clustered[std::size_t(scene.nodes[n].mesh)], h.world[n]);
  });
}

// Subtree boxes, triangle and mesh node counts, children into parents, from the instances' boxes.
void sumSubtrees(const Scene& scene, Hierarchy& h) {
  for (std::uint32_t n : h.preorder) {
    if (scene.nodes[n].mesh < 0) continue;
    h.worldBounds[n] = h.instanceBounds[n];
    h.subtreeTriangles[n] = scene.meshes[std::size_t(scene.nodes[n].mesh)].triangleCount();
    h.subtreeMeshNodes[n] = 1;
  }
  for (auto it = h.preorder.rbegin(); it != h.preorder.rend(); ++it) {
    const std::int32_t p = h.parent[*it];
    if (p < 0) continue;
    h.worldBounds[p].extend(h.worldBounds[*it]);
    h.subtreeTriangles[p] += h.subtreeTriangles[*it];
    h.subtreeMeshNodes[p] += h.subtreeMeshNodes[*it];
  }
}

Hierarchy analyzeFrom(const Scene& scene, std::span<const std::uint32_t> starts, bool startsInOwnFrame) {
  Hierarchy h = walkFrom(scene, starts, startsInOwnFrame);
  boundInstances(scene, h);
  sumSubtrees(scene, h);
  return h;
}

}  // namespace

Hierarchy analyzeHierarchy(const Scene& scene) { return analyzeFrom(scene, scene.roots, false); }

Hierarchy analyzeHierarchy(const Scene& scene, std::span<const Bounds> instanceBounds) {
  if (instanceBounds.size() != scene.nodes.size())
    throw std::invalid_argument("analyzeHierarchy: " + std::to_string(instanceBounds.size()) + " instance boxes for " +
                                std::to_string(scene.nodes.size()) + " nodes");
  for (std::size_t n = 0; n < scene.nodes.size(); ++n)
    if (scene.nodes[n].mesh < 0 && !instanceBounds[n].empty())
      throw std::invalid_argument("analyzeHierarchy: node " + std::to_string(n) + " has no mesh but a box");
  Hierarchy h = walkFrom(scene, scene.roots, false);
  h.instanceBounds.assign(instanceBounds.begin(), instanceBounds.end());
  sumSubtrees(scene, h);
  return h;
}

Hierarchy analyzeStructure(const Scene& scene) {
  return analyzeHierarchy(scene, std::vector<Bounds>(scene.nodes.size()));
}

Hierarchy analyzeSubtree(const Scene& scene, std::uint32_t node) {
  const std::uint32_t start[] = {node};
  return analyzeFrom(scene, start, true);
}

std::vector<SubtreeInstance> subtreeInstances(const Scene& scene, std::uint32_t node) {
  // walkFrom's walk, with each transform on the stack instead of in a per-scene array: children pushed
  // last to first, so popped first to last; world of a child = world of its parent × its local.
  std::vector<SubtreeInstance> instances;
  std::vector<std::pair<std::uint32_t, glm::dmat4>> stack{{node, glm::dmat4(1.0)}};
  while (!stack.empty()) {
    const auto [n, world] = stack.back();
    stack.pop_back();
    const Node& current = scene.nodes[n];
    if (current.mesh >= 0) instances.push_back({n, world});
    for (auto child = current.children.rbegin(); child != current.children.rend(); ++child)
      stack.emplace_back(*child, world * scene.nodes[*child].local);
  }
  return instances;
}

Hierarchy analyzeSubtree(const Scene& scene, std::uint32_t node, std::span<const Bounds> instanceBounds) {
  const std::uint32_t start[] = {node};
  Hierarchy h = walkFrom(scene, start, true);
  std::size_t instances = 0;
  for (std::uint32_t n : h.preorder) {
    if (scene.nodes[n].mesh < 0) continue;
    if (instances < instanceBounds.size()) h.instanceBounds[n] = instanceBounds[instances];
    ++instances;
  }
  if (instances != instanceBounds.size())
    throw std::invalid_argument("analyzeSubtree: " + std::to_string(instanceBounds.size()) + " instance boxes for " +
                                std::to_string(instances) + " instances");
  sumSubtrees(scene, h);
  return h;
}

SceneSummary summarizeScene(const Scene& scene, const Hierarchy& hierarchy) {
  SceneSummary s;
  s.nodes = hierarchy.preorder.size();
  s.meshes = scene.meshes.size();
  s.materials = scene.materials.size();
  s.textures = scene.textures.size();
  for (const Mesh& mesh : scene.meshes) s.uniqueTriangles += mesh.triangleCount();
  for (std::uint32_t n : hierarchy.preorder) {
    if (scene.nodes[n].mesh >= 0) ++s.instances;
    s.maxDepth = std::max(s.maxDepth, hierarchy.depth[n]);
  }
  for (std::uint32_t root : scene.roots) {
    s.triangles += hierarchy.subtreeTriangles[root];
    s.bounds.extend(hierarchy.worldBounds[root]);
  }
  return s;
}

}  // namespace pbs
