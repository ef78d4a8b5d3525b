// Tests of buildLooseOctree: leaves within the triangle budget, the same world-space triangles and
// bounds, shared pieces for instances, degenerate inputs and determinism; when a scene needs one, and the
// generated terrain that does.
#include "pbs/raster/thread_arena.hpp"
#include "pbs/scene/generate.hpp"
#include "pbs/scene/gltf_import.hpp"
#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/loose_octree.hpp"
#include "test_fixtures.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <string>
#include <vector>

namespace pbs {
namespace {

// Two materials, so that parts and the material of every triangle are checked too.
std::vector<Material> twoMaterials() {
  Material red, blue;
  red.name = "red";
  red.baseColorFactor = {1, 0, 0, 1};
  blue.name = "blue";
  blue.baseColorFactor = {0, 0, 1, 1};
  return {red, blue};
}

// Closes a mesh built from positions, uvs and indices: normals, bounds, and two parts that split
// the triangles at half (material 0, then material 1).
Mesh finishMesh(std::string name, std::vector<glm::vec3> positions, std::vector<glm::vec2> uvs,
                std::vector<std::uint32_t> indices) {
  Mesh mesh;
  mesh.name = std::move(name);
  mesh.positions = std::move(positions);
  mesh.uvs = std::move(uvs);
  mesh.indices = std::move(indices);
  mesh.normals = computeVertexNormals(mesh.positions, mesh.indices);
  const auto half = static_cast<std::uint32_t>(mesh.triangleCount() / 2 * 3);
  mesh.parts = {{0, half, 0}, {half, static_cast<std::uint32_t>(mesh.indices.size()) - half, 1}};
  if (half == 0) mesh.parts.erase(mesh.parts.begin());
  updateMeshBounds(mesh);
  return mesh;
}

// A UV sphere of radius 1 with `slices` × `stacks` quads (two triangles each, poles included).
Mesh sphereMesh(std::uint32_t slices, std::uint32_t stacks) {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec2> uvs;
  for (std::uint32_t j = 0; j <= stacks; ++j) {
    for (std::uint32_t i = 0; i <= slices; ++i) {
      const double u = double(i) / slices, v = double(j) / stacks;
      const double phi = 2 * std::numbers::pi * u, theta = std::numbers::pi * v;
      positions.emplace_back(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      uvs.emplace_back(u, v);
    }
  }
  std::vector<std::uint32_t> indices;
  for (std::uint32_t j = 0; j < stacks; ++j) {
    for (std::uint32_t i = 0; i < slices; ++i) {
      const std::uint32_t a = j * (slices + 1) + i, b = a + 1, c = a + slices + 1, d = c + 1;
      indices.insert(indices.end(), {a, c, b, b, c, d});
    }
  }
  return finishMesh("sphere", std::move(positions), std::move(uvs), std::move(indices));
}

// A flat grid of `n` × `n` unit quads in the plane z = 0: a zero-thickness mesh.
Mesh gridMesh(std::uint32_t n) {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec2> uvs;
  for (std::uint32_t j = 0; j <= n; ++j) {
    for (std::uint32_t i = 0; i <= n; ++i) {
      positions.emplace_back(float(i), float(j), 0.0f);
      uvs.emplace_back(float(i) / n, float(j) / n);
    }
  }
  std::vector<std::uint32_t> indices;
  for (std::uint32_t j = 0; j < n; ++j) {
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      indices.insert(indices.end(), {a, b, c, b, d, c});
    }
  }
  return finishMesh("grid", std::move(positions), std::move(uvs), std::move(indices));
}

// A unit cube of 12 triangles without uvs.
Mesh boxMesh(std::string name) {
  std::vector<glm::vec3> positions;
  for (int corner = 0; corner < 8; ++corner) positions.emplace_back(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
  std::vector<std::uint32_t> indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                        2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  return finishMesh(std::move(name), std::move(positions), {}, std::move(indices));
}

// `count` triangles, all the same one.
Mesh coincidentMesh(std::uint32_t count) {
  std::vector<std::uint32_t> indices;
  for (std::uint32_t t = 0; t < count; ++t) indices.insert(indices.end(), {0, 1, 2});
  return finishMesh("coincident", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {}, std::move(indices));
}

// A scene of one root node with the transform `rootTransform` above `transforms.size()` children,
// child k drawing mesh `meshOf[k]`.
Scene sceneUnderOneRoot(std::vector<Mesh> meshes, const std::vector<glm::dmat4>& transforms,
                        const std::vector<std::int32_t>& meshOf, const glm::dmat4& rootTransform = glm::dmat4(1.0)) {
  Scene scene;
  scene.meshes = std::move(meshes);
  scene.materials = twoMaterials();
  Node root;
  root.name = "root";
  root.local = rootTransform;
  scene.nodes.push_back(root);
  scene.roots = {0};
  for (std::size_t k = 0; k < transforms.size(); ++k) {
    Node child;
    child.name = "item " + std::to_string(k);
    child.local = transforms[k];
    child.mesh = meshOf[k];
    scene.nodes[0].children.push_back(static_cast<std::uint32_t>(scene.nodes.size()));
    scene.nodes.push_back(child);
  }
  return scene;
}

Scene singleMeshScene(Mesh mesh, const glm::dmat4& transform = glm::dmat4(1.0)) {
  return sceneUnderOneRoot({std::move(mesh)}, {transform}, {0});
}

glm::dmat4 someTransform(double seed) {
  glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(1000.0 + seed * 3.0, -20.0 + seed, 7.5 * seed));
  m = glm::rotate(m, 0.3 + seed, glm::normalize(glm::dvec3(1.0, 2.0, 3.0 + seed)));
  return glm::scale(m, glm::dvec3(2.0, 0.5 + 0.01 * seed, seed > 25 ? -1.5 : 1.5));
}

// A drawn triangle as its world-space corners followed by its local normals, uvs (zero when the
// mesh has none) and material: equal multisets of these mean the same geometry drawn the same way.
using TriangleKey = std::array<double, 25>;

TriangleKey triangleKey(const Mesh& mesh, std::uint32_t firstIndex, std::uint32_t material, const glm::dmat4& world) {
  TriangleKey key{};
  for (std::uint32_t c = 0; c < 3; ++c) {
    const std::uint32_t v = mesh.indices[firstIndex + c];
    const glm::dvec3 p(world * glm::dvec4(glm::dvec3(mesh.positions[v]), 1.0));
    const glm::vec2 uv = mesh.uvs.empty() ? glm::vec2(0.0f) : mesh.uvs[v];
    const glm::vec3 normal = mesh.normals[v];
    const std::array<double, 8> corner = {p.x, p.y, p.z, normal.x, normal.y, normal.z, uv.x, uv.y};
    std::copy(corner.begin(), corner.end(), key.begin() + 8 * c);
  }
  key[24] = material;
  return key;
}

// Every drawn triangle's key, instances counted, sorted.
std::vector<TriangleKey> worldTriangles(const Scene& scene) {
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  std::vector<TriangleKey> triangles;
  for (const std::uint32_t n : hierarchy.preorder) {
    if (scene.nodes[n].mesh < 0) continue;
    const Mesh& mesh = scene.meshes[scene.nodes[n].mesh];
    for (const MeshPart& part : mesh.parts)
      for (std::uint32_t i = part.firstIndex; i < part.firstIndex + part.indexCount; i += 3)
        triangles.push_back(triangleKey(mesh, i, part.material, hierarchy.world[n]));
  }
  std::sort(triangles.begin(), triangles.end());
  return triangles;
}

struct OctreeShape {
  std::uint64_t leaves = 0;  // octree leaves: groups of items within the budget, and items elsewhere
  std::uint64_t maxLeafTriangles = 0;
  std::uint32_t depth = 0;  // of the deepest node
};

// Checks what every result must satisfy and returns its shape: valid, the input's world triangles
// and bounds, inner nodes without transform or mesh, item nodes without children and within the
// budget. A group of items only is a leaf when within the budget; else it is a cell whose every
// child holds a single item, which has at most 8 children.
OctreeShape checkOctree(const Scene& input, const Scene& result, std::uint32_t maxLeafTriangles) {
  EXPECT_NO_THROW(validateScene(result, "octree"));
  const Hierarchy in = analyzeHierarchy(input);
  const Hierarchy out = analyzeHierarchy(result);
  const SceneSummary before = summarizeScene(input, in);
  const SceneSummary after = summarizeScene(result, out);
  EXPECT_EQ(after.triangles, before.triangles);
  EXPECT_EQ(after.bounds.min, before.bounds.min);
  EXPECT_EQ(after.bounds.max, before.bounds.max);
  EXPECT_EQ(result.roots.size(), before.triangles > 0 ? 1u : 0u);
  EXPECT_TRUE(worldTriangles(input) == worldTriangles(result)) << "world-space triangles differ";

  const auto isItem = [&](std::uint32_t n) { return result.nodes[n].mesh >= 0; };
  const auto isGroupLeaf = [&](std::uint32_t n) {
    const Node& node = result.nodes[n];
    return !isItem(n) && std::all_of(node.children.begin(), node.children.end(), isItem) &&
           out.subtreeTriangles[n] <= maxLeafTriangles;
  };
  OctreeShape shape;
  for (const std::uint32_t n : out.preorder) {
    const Node& node = result.nodes[n];
    shape.depth = std::max(shape.depth, out.depth[n]);
    if (isItem(n)) {
      EXPECT_TRUE(node.children.empty()) << node.name;
      EXPECT_LE(result.meshes[node.mesh].triangleCount(), maxLeafTriangles) << node.name;
    } else {
      EXPECT_EQ(node.local, glm::dmat4(1.0)) << node.name;
      EXPECT_FALSE(node.children.empty()) << node.name;
      EXPECT_EQ(node.name.rfind("octree", 0), 0u) << node.name;
      if (std::all_of(node.children.begin(), node.children.end(), isItem)) {
        EXPECT_TRUE(isGroupLeaf(n) || node.children.size() <= 8) << node.name;
      }
    }
    if (isGroupLeaf(n) || (isItem(n) && !(out.parent[n] >= 0 && isGroupLeaf(out.parent[n])))) {
      ++shape.leaves;
      shape.maxLeafTriangles = std::max(shape.maxLeafTriangles, out.subtreeTriangles[n]);
    }
  }
  return shape;
}

bool sameScene(const Scene& a, const Scene& b) {
  if (a.roots != b.roots || a.nodes.size() != b.nodes.size() || a.meshes.size() != b.meshes.size()) return false;
  for (std::size_t n = 0; n < a.nodes.size(); ++n) {
    const Node &x = a.nodes[n], &y = b.nodes[n];
    if (x.name != y.name || x.local != y.local || x.children != y.children || x.mesh != y.mesh) return false;
  }
  for (std::size_t m = 0; m < a.meshes.size(); ++m) {
    const Mesh &x = a.meshes[m], &y = b.meshes[m];
    if (x.name != y.name || x.positions != y.positions || x.normals != y.normals || x.uvs != y.uvs ||
        x.indices != y.indices || x.parts.size() != y.parts.size())
      return false;
    for (std::size_t p = 0; p < x.parts.size(); ++p)
      if (x.parts[p].firstIndex != y.parts[p].firstIndex || x.parts[p].indexCount != y.parts[p].indexCount ||
          x.parts[p].material != y.parts[p].material)
        return false;
  }
  return true;
}

TEST(LooseOctree, SplitsOneLargeMeshIntoLeavesWithinTheBudget) {
  const Scene input = singleMeshScene(sphereMesh(250, 200), someTransform(1.0));  // 100,000 triangles
  ASSERT_EQ(input.meshes[0].triangleCount(), 100000u);
  const Scene result = buildLooseOctree(input, 1000);
  const OctreeShape shape = checkOctree(input, result, 1000);
  EXPECT_GT(shape.depth, 1u);
  EXPECT_GE(shape.leaves, 100u);
  EXPECT_GT(result.meshes.size(), 100u);
  for (const Mesh& piece : result.meshes) EXPECT_EQ(piece.name.rfind("sphere piece ", 0), 0u) << piece.name;
}

TEST(LooseOctree, PiecesHaveCompactVerticesAndSourceOrder) {
  const Mesh sphere = sphereMesh(100, 50);
  const Scene result = buildLooseOctree(singleMeshScene(sphere), 300);

  // Every sphere triangle is unique (uvs tell the pole triangles apart), so its key finds its index.
  std::map<TriangleKey, std::uint32_t> sourceIndex;
  for (const MeshPart& part : sphere.parts)
    for (std::uint32_t i = part.firstIndex; i < part.firstIndex + part.indexCount; i += 3)
      sourceIndex[triangleKey(sphere, i, part.material, glm::dmat4(1.0))] = i / 3;
  ASSERT_EQ(sourceIndex.size(), sphere.triangleCount());

  std::uint64_t vertices = 0;
  for (const Mesh& piece : result.meshes) {
    std::vector<bool> used(piece.positions.size(), false);
    for (const std::uint32_t v : piece.indices) used[v] = true;
    EXPECT_TRUE(std::all_of(used.begin(), used.end(), [](bool u) { return u; })) << piece.name;
    EXPECT_EQ(piece.normals.size(), piece.positions.size());
    EXPECT_EQ(piece.uvs.size(), piece.positions.size());
    vertices += piece.positions.size();

    std::int64_t previous = -1;
    for (const MeshPart& part : piece.parts) {
      for (std::uint32_t i = part.firstIndex; i < part.firstIndex + part.indexCount; i += 3) {
        const std::int64_t index = sourceIndex.at(triangleKey(piece, i, part.material, glm::dmat4(1.0)));
        EXPECT_GT(index, previous) << piece.name;
        previous = index;
      }
    }
  }
  // Shared borders duplicate some vertices, but far fewer than all of them.
  EXPECT_LT(vertices, sphere.positions.size() * 2);
}

TEST(LooseOctree, GroupsManySmallMeshesIntoLeaves) {
  std::vector<Mesh> meshes;
  std::vector<glm::dmat4> transforms;
  std::vector<std::int32_t> meshOf;
  for (std::int32_t k = 0; k < 5000; ++k) {
    meshes.push_back(boxMesh("box " + std::to_string(k)));
    transforms.push_back(glm::translate(glm::dmat4(1.0), glm::dvec3(k % 20, (k / 20) % 25, k / 500) * 3.0));
    meshOf.push_back(k);
  }
  const Scene input = sceneUnderOneRoot(std::move(meshes), transforms, meshOf, someTransform(2.0));
  const Scene result = buildLooseOctree(input, 1000);
  const OctreeShape shape = checkOctree(input, result, 1000);
  EXPECT_EQ(result.meshes.size(), 5000u);
  EXPECT_GE(shape.leaves, 60u);             // 60,000 triangles in leaves of at most 1000
  EXPECT_GT(shape.maxLeafTriangles, 500u);  // and the leaves are reasonably full
}

TEST(LooseOctree, InstancesOfASplitMeshShareThePieces) {
  std::vector<glm::dmat4> transforms;
  for (int k = 0; k < 50; ++k) transforms.push_back(someTransform(k));
  const Scene input = sceneUnderOneRoot({gridMesh(60)}, transforms, std::vector<std::int32_t>(50, 0));
  const Scene result = buildLooseOctree(input, 1000);
  checkOctree(input, result, 1000);
  EXPECT_GE(result.meshes.size(), 8u);  // 7,200 triangles in pieces of at most 1000
  EXPECT_LT(result.meshes.size(), 50u);
  std::uint64_t itemNodes = 0;
  for (const Node& node : result.nodes) itemNodes += node.mesh >= 0;
  EXPECT_EQ(itemNodes, result.meshes.size() * 50);
}

TEST(LooseOctree, SmallMeshesAreKeptWhole) {
  const Scene input = singleMeshScene(boxMesh("box"), someTransform(3.0));
  const Scene result = buildLooseOctree(input, 1000);
  checkOctree(input, result, 1000);
  ASSERT_EQ(result.nodes.size(), 1u);  // the item node itself is the root
  EXPECT_EQ(result.nodes[0].name, "item 0");
  EXPECT_EQ(result.nodes[0].local, someTransform(3.0));
  EXPECT_EQ(result.meshes[0].name, "box");
}

TEST(LooseOctree, KeepsNestedTransformsAndDropsEmptyNodes) {
  Scene input = singleMeshScene(sphereMesh(40, 20), someTransform(4.0));
  input.meshes.push_back(Mesh{});  // a mesh without triangles
  input.nodes[1].children = {2, 3};
  Node nested;
  nested.name = "nested";
  nested.local = someTransform(5.0);
  nested.mesh = 0;
  input.nodes.push_back(nested);
  Node empty;
  empty.name = "empty";
  empty.mesh = 1;
  input.nodes.push_back(empty);
  validateScene(input, "input");
  const Scene result = buildLooseOctree(input, 100);
  checkOctree(input, result, 100);
}

TEST(LooseOctree, CoincidentTrianglesAreSplitByOrder) {
  const Scene input = singleMeshScene(coincidentMesh(5000));
  const Scene result = buildLooseOctree(input, 100);
  checkOctree(input, result, 100);
  EXPECT_EQ(result.meshes.size(), 64u);  // 5000 halved six times: pieces of 78 or 79
}

TEST(LooseOctree, CoincidentInstancesAreSplitByOrder) {
  const Scene input = sceneUnderOneRoot({boxMesh("box")}, std::vector<glm::dmat4>(100, someTransform(6.0)),
                                        std::vector<std::int32_t>(100, 0));
  const Scene result = buildLooseOctree(input, 12);
  const OctreeShape shape = checkOctree(input, result, 12);
  EXPECT_EQ(shape.leaves, 100u);
}

TEST(LooseOctree, PlanarMeshSplits) {
  const Scene input = singleMeshScene(gridMesh(150));
  const Scene result = buildLooseOctree(input, 500);
  const OctreeShape shape = checkOctree(input, result, 500);
  EXPECT_GE(shape.leaves, 90u);
}

TEST(LooseOctree, OneTrianglePerLeaf) {
  const Scene input = singleMeshScene(sphereMesh(20, 10), someTransform(7.0));
  const Scene result = buildLooseOctree(input, 1);
  const OctreeShape shape = checkOctree(input, result, 1);
  EXPECT_EQ(result.meshes.size(), 400u);
  EXPECT_EQ(shape.leaves, 400u);
}

TEST(LooseOctree, EmptySceneGivesEmptyScene) {
  const Scene result = buildLooseOctree(Scene{}, 10);
  EXPECT_TRUE(result.nodes.empty());
  EXPECT_TRUE(result.roots.empty());
}

TEST(LooseOctree, RejectsAZeroBudget) {
  EXPECT_THROW(buildLooseOctree(singleMeshScene(boxMesh("box")), 0), std::invalid_argument);
}

TEST(LooseOctree, IsDeterministic) {
  std::vector<glm::dmat4> transforms;
  for (int k = 0; k < 30; ++k) transforms.push_back(someTransform(k));
  std::vector<std::int32_t> meshOf(30);
  for (int k = 0; k < 30; ++k) meshOf[k] = k % 3;
  const Scene input = sceneUnderOneRoot({sphereMesh(60, 40), gridMesh(40), boxMesh("box")}, transforms, meshOf);
  const Scene first = buildLooseOctree(input, 700);
  Scene second, oneThread;
  second = buildLooseOctree(input, 700);
  runWithThreads(1, [&] { oneThread = buildLooseOctree(input, 700); });
  EXPECT_TRUE(sameScene(first, second));
  EXPECT_TRUE(sameScene(first, oneThread));
  checkOctree(input, first, 700);
}

TEST(LooseOctree, Bunny) {
  PBS_SHARED_SCENE(file, "bunny.glb");
  const Scene input = importGltf(file).scene;
  const Scene result = buildLooseOctree(input, 1000);
  const OctreeShape shape = checkOctree(input, result, 1000);
  EXPECT_GT(shape.depth, 1u);
  EXPECT_GE(shape.leaves, 70u);
}

}  // namespace
}  // namespace pbs

namespace pbs {
namespace {

// A generated terrain is one mesh under one node, as large as asked, the same for any seed's repeat.
TEST(Terrain, OneFlatMeshOfAtLeastTheTrianglesAskedAndDeterministic) {
  const Scene terrain = generateTerrain({.triangles = 5000, .size = 100.0, .seed = 3});
  validateScene(terrain, "terrain");
  ASSERT_EQ(terrain.nodes.size(), 1u);
  ASSERT_EQ(terrain.meshes.size(), 1u);
  EXPECT_EQ(terrain.meshes[0].triangleCount(), 2u * 50u * 50u);  // the least square grid of ≥ 5000
  const Bounds& box = terrain.meshes[0].bounds;
  EXPECT_FLOAT_EQ(float(box.max.x - box.min.x), 100.0f);
  EXPECT_GT(box.max.y - box.min.y, 1.0) << "hills, not a plane";
  const Scene again = generateTerrain({.triangles = 5000, .size = 100.0, .seed = 3});
  EXPECT_EQ(again.meshes[0].positions, terrain.meshes[0].positions);
  EXPECT_NE(generateTerrain({.triangles = 5000, .size = 100.0, .seed = 4}).meshes[0].positions,
            terrain.meshes[0].positions);
  EXPECT_THROW(generateTerrain({.triangles = 0}), std::invalid_argument);
}

// A scene needs the octree when one node draws a mesh above the limit; instancing small meshes does not
// count, nor does a limit of 0.
TEST(LooseOctree, NeededWhenANodeDrawsAMeshAboveTheLimit) {
  const Scene terrain = generateTerrain({.triangles = 5000});
  EXPECT_TRUE(needsLooseOctree(terrain, 4999));
  EXPECT_FALSE(needsLooseOctree(terrain, 5000));
  EXPECT_FALSE(needsLooseOctree(terrain, 0));
  const Scene groups = test::twoIdenticalGroups();  // four instances of one 1,200-triangle box
  EXPECT_FALSE(needsLooseOctree(groups, 1200));
  EXPECT_TRUE(needsLooseOctree(groups, 1199));
}

}  // namespace
}  // namespace pbs
