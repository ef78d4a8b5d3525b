// Gives flat scenes a hierarchy: meshes are split into pieces of at most N triangles, then a loose
// octree over the pieces' instances groups them into leaves of at most N triangles.
#include "pbs/scene/loose_octree.hpp"

#include "mesh_split.hpp"
#include "octree_walk.hpp"
#include "pbs/scene/hierarchy.hpp"

#include <tbb/parallel_for.h>

#include <numeric>
#include <span>
#include <stdexcept>
#include <string>

namespace pbs {
namespace {

// Where a source mesh's pieces lie in the result's meshes.
struct PieceRange {
  std::uint32_t first = 0;
  std::uint32_t count = 0;  // 0: the mesh draws nothing and is dropped
};

// One piece of one mesh instance: what the octree sorts.
struct Item {
  std::uint32_t node = 0;   // source node: name and world transform
  std::uint32_t mesh = 0;   // index into the result's meshes
  std::int32_t piece = -1;  // number within its source mesh's pieces; -1 when the mesh was not split
};

// Splits every mesh that some reachable node draws, once per mesh so that its instances keep
// sharing the pieces, and appends the pieces to `meshes` in source mesh order.
std::vector<PieceRange> splitDrawnMeshes(const Scene& scene, const Hierarchy& hierarchy, std::uint32_t maxLeafTriangles,
                                         std::vector<Mesh>& meshes) {
  std::vector<char> drawn(scene.meshes.size(), 0);
  for (const std::uint32_t node : hierarchy.preorder) {
    const std::int32_t mesh = scene.nodes[node].mesh;
    if (mesh >= 0 && scene.meshes[mesh].triangleCount() > 0) drawn[mesh] = 1;
  }
  std::vector<std::vector<Mesh>> pieces(scene.meshes.size());
  tbb::parallel_for(std::size_t(0), scene.meshes.size(), [&](std::size_t m) {
    if (drawn[m]) pieces[m] = detail::splitMesh(scene.meshes[m], maxLeafTriangles);
  });
  std::vector<PieceRange> ranges(scene.meshes.size());
  for (std::size_t m = 0; m < pieces.size(); ++m) {
    ranges[m] = {static_cast<std::uint32_t>(meshes.size()), static_cast<std::uint32_t>(pieces[m].size())};
    for (Mesh& piece : pieces[m]) meshes.push_back(std::move(piece));
  }
  return ranges;
}

std::vector<Item> listItems(const Scene& scene, const Hierarchy& hierarchy, const std::vector<PieceRange>& ranges) {
  std::vector<Item> items;
  for (const std::uint32_t node : hierarchy.preorder) {
    const std::int32_t mesh = scene.nodes[node].mesh;
    if (mesh < 0) continue;
    const PieceRange range = ranges[mesh];
    for (std::uint32_t k = 0; k < range.count; ++k)
      items.push_back({node, range.first + k, range.count > 1 ? static_cast<std::int32_t>(k) : -1});
  }
  return items;
}

// The centre of each item's exact world box. A node without children drawing an unsplit mesh
// already has that box in the hierarchy; pieces need their own vertices transformed.
std::vector<glm::dvec3> itemCentres(const Scene& scene, const Hierarchy& hierarchy, const std::vector<Mesh>& meshes,
                                    const std::vector<Item>& items) {
  std::vector<glm::dvec3> centres(items.size());
  tbb::parallel_for(std::size_t(0), items.size(), [&](std::size_t i) {
    const Item& item = items[i];
    if (item.piece < 0 && scene.nodes[item.node].children.empty()) {
      centres[i] = hierarchy.worldBounds[item.node].center();
      return;
    }
    const glm::dmat4& world = hierarchy.world[item.node];
    Bounds box;
    for (const glm::vec3& p : meshes[item.mesh].positions)
      box.extend(glm::dvec3(world * glm::dvec4(glm::dvec3(p), 1.0)));
    centres[i] = box.center();
  });
  return centres;
}

Node itemNode(const Scene& scene, const Hierarchy& hierarchy, const Item& item) {
  Node node;
  node.name = scene.nodes[item.node].name;
  if (item.piece >= 0) node.name += " piece " + std::to_string(item.piece);
  node.local = hierarchy.world[item.node];  // every ancestor in the result is the identity
  node.mesh = static_cast<std::int32_t>(item.mesh);
  return node;
}

// Adds the octree over `items` to `result`: group nodes for inner cells and leaves of several
// items, item nodes for the items, one root.
void addOctreeNodes(const Scene& scene, const Hierarchy& hierarchy, const std::vector<Item>& items,
                    const std::vector<glm::dvec3>& centres, std::uint32_t maxLeafTriangles, Scene& result) {
  std::vector<std::uint32_t> order(items.size());
  std::iota(order.begin(), order.end(), 0u);
  const auto fitsLeaf = [&](std::span<const std::uint32_t> cell) {
    std::uint64_t triangles = 0;
    for (const std::uint32_t i : cell) triangles += result.meshes[items[i].mesh].triangleCount();
    return triangles <= maxLeafTriangles;
  };

  // Per visited cell: its node in the result and its path of child slots, which names it.
  std::vector<std::uint32_t> cellNode;
  std::vector<std::string> cellPath;
  const auto addNode = [&](Node node) {
    result.nodes.push_back(std::move(node));
    return static_cast<std::uint32_t>(result.nodes.size() - 1);
  };
  detail::walkOctree<glm::dvec3>(order, centres, fitsLeaf, [&](const detail::OctreeCell& cell) {
    std::string path;
    if (cell.parent >= 0) {
      const std::string& parentPath = cellPath[cell.parent];
      path = (parentPath.empty() ? "" : parentPath + "/") + std::to_string(cell.slot);
    }
    std::uint32_t index;
    if (cell.leaf && cell.end - cell.begin == 1) {
      index = addNode(itemNode(scene, hierarchy, items[order[cell.begin]]));
    } else {
      Node group;
      group.name = path.empty() ? "octree" : "octree " + path;
      index = addNode(std::move(group));
      if (cell.leaf) {
        for (std::uint32_t i = cell.begin; i < cell.end; ++i) {
          const std::uint32_t child = addNode(itemNode(scene, hierarchy, items[order[i]]));
          result.nodes[index].children.push_back(child);
        }
      }
    }
    if (cell.parent < 0) {
      result.roots.push_back(index);
    } else {
      result.nodes[cellNode[cell.parent]].children.push_back(index);
    }
    cellNode.push_back(index);
    cellPath.push_back(std::move(path));
  });
}

}  // namespace

Scene buildLooseOctree(const Scene& scene, std::uint32_t maxLeafTriangles) {
  if (maxLeafTriangles == 0) throw std::invalid_argument("buildLooseOctree: maxLeafTriangles must be at least 1");
  const Hierarchy hierarchy = analyzeHierarchy(scene);

  Scene result;
  result.materials = scene.materials;
  result.textures = scene.textures;
  const std::vector<PieceRange> ranges = splitDrawnMeshes(scene, hierarchy, maxLeafTriangles, result.meshes);
  const std::vector<Item> items = listItems(scene, hierarchy, ranges);
  const std::vector<glm::dvec3> centres = itemCentres(scene, hierarchy, result.meshes, items);
  addOctreeNodes(scene, hierarchy, items, centres, maxLeafTriangles, result);
  return result;
}

bool needsLooseOctree(const Scene& scene, std::uint64_t aboveTriangles) {
  if (aboveTriangles == 0) return false;
  for (const Node& node : scene.nodes)
    if (node.mesh >= 0 && scene.meshes[std::size_t(node.mesh)].triangleCount() > aboveTriangles) return true;
  return false;
}

}  // namespace pbs
