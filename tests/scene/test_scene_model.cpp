// Tests of the scene model: validation, world transforms, exact world bounds, subtree counts, finding a
// node by name or index.
#include "test_fixtures.hpp"

#include <pbs/scene/find_node.hpp>
#include <pbs/scene/hierarchy.hpp>
#include <pbs/scene/input_error.hpp>
#include <pbs/surfels/surfel_nodes.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace pbs {
namespace {

// A mesh of points on the unit circle in the XY plane (a fan of `segments` triangles): its exact
// rotated bounds are known in closed form, unlike those of a box.
Mesh circleFan(int segments) {
  Mesh mesh;
  mesh.positions.push_back({0, 0, 0});
  for (int i = 0; i < segments; ++i) {
    const double a = 2.0 * std::numbers::pi * i / segments;
    mesh.positions.push_back({float(std::cos(a)), float(std::sin(a)), 0.0f});
  }
  for (int i = 0; i < segments; ++i) {
    mesh.indices.insert(mesh.indices.end(), {0u, std::uint32_t(1 + i), std::uint32_t(1 + (i + 1) % segments)});
  }
  mesh.normals = computeVertexNormals(mesh.positions, mesh.indices);
  mesh.parts.push_back({0, std::uint32_t(mesh.indices.size()), 0});
  updateMeshBounds(mesh);
  return mesh;
}

Scene singleMeshScene(Mesh mesh, const glm::dmat4& transform) {
  Scene scene;
  scene.materials.push_back({});
  scene.meshes.push_back(std::move(mesh));
  Node node;
  node.local = transform;
  node.mesh = 0;
  scene.nodes.push_back(node);
  scene.roots.push_back(0);
  return scene;
}

std::string validationMessage(const Scene& scene) {
  try {
    validateScene(scene, "test.glb");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(WorldBounds, RotationGivesTheExactBoxNotTheRotatedCorners) {
  // 720 points on the unit circle rotated by 30° about Z: the tight box is still [-1,1]² up to the
  // sampling of the circle, whereas transforming the local box's corners would give ±1.366.
  const glm::dmat4 rotation = glm::rotate(glm::dmat4(1.0), std::numbers::pi / 6, glm::dvec3(0, 0, 1));
  const Scene scene = singleMeshScene(circleFan(720), rotation);
  validateScene(scene, "circle");
  const Hierarchy h = analyzeHierarchy(scene);
  const Bounds& b = h.worldBounds[0];
  const double sampling = 1.0 - std::cos(std::numbers::pi / 720);  // largest gap between chord and circle
  EXPECT_NEAR(b.max.x, 1.0, sampling + 1e-6);
  EXPECT_NEAR(b.min.x, -1.0, sampling + 1e-6);
  EXPECT_NEAR(b.max.y, 1.0, sampling + 1e-6);
  EXPECT_NEAR(b.min.y, -1.0, sampling + 1e-6);
  EXPECT_EQ(b.min.z, 0.0);
  EXPECT_EQ(b.max.z, 0.0);
  EXPECT_GT(transformCorners(scene.meshes[0].bounds, rotation).max.x, 1.3);
}

TEST(WorldBounds, NonUniformAndNegativeScaleThroughTheHierarchy) {
  // Parent: translate (10,0,0) and mirror X; child: scale (2,3,0.5) and rotate 90° about Z.
  Scene scene = singleMeshScene(circleFan(4), glm::dmat4(1.0));  // points (±1,0,0), (0,±1,0), origin
  Node parent;
  parent.local = glm::scale(glm::translate(glm::dmat4(1.0), {10, 0, 0}), {-1, 1, 1});
  parent.children = {0};
  scene.nodes[0].local = glm::rotate(glm::scale(glm::dmat4(1.0), {2, 3, 0.5}), std::numbers::pi / 2, {0, 0, 1});
  scene.nodes.push_back(parent);
  scene.roots = {1};
  validateScene(scene, "mirror");
  const Hierarchy h = analyzeHierarchy(scene);
  // Child maps (x,y) → rotate → (-y, x) → scale → (-2y, 3x); mirror → (2y, 3x); +10 in x.
  const Bounds& b = h.worldBounds[1];
  EXPECT_NEAR(b.min.x, 8.0, 1e-12);
  EXPECT_NEAR(b.max.x, 12.0, 1e-12);
  EXPECT_NEAR(b.min.y, -3.0, 1e-12);
  EXPECT_NEAR(b.max.y, 3.0, 1e-12);
  EXPECT_LT(glm::determinant(h.world[0]), 0.0);
  EXPECT_EQ(h.depth[0], 1u);
  EXPECT_EQ(h.parent[0], 1);
}

TEST(WorldBounds, PrunedSearchEqualsTransformingEveryVertex) {
  // A random cloud (clusters of it far apart, so pruning has work to do) under rotations, non-uniform
  // and mirroring scales and far translations: the result must equal the brute-force box exactly. The
  // sizes give the search's tree one cluster; a top level of exactly 16 clusters; 17 (a level above);
  // and three and four levels.
  std::mt19937_64 random(7);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  for (const int points : {5, 1024, 1025, 20000, 300000}) {
    Mesh mesh;
    for (int i = 0; i < points; ++i)
      mesh.positions.push_back(glm::vec3(unit(random), unit(random), unit(random)) * (i % 3 == 0 ? 50.0f : 1.0f));
    for (std::uint32_t i = 0; i + 2 < mesh.positions.size(); i += 3)
      mesh.indices.insert(mesh.indices.end(), {i, i + 1, i + 2});
    mesh.normals = computeVertexNormals(mesh.positions, mesh.indices);
    mesh.parts.push_back({0, std::uint32_t(mesh.indices.size()), 0});
    updateMeshBounds(mesh);
    for (int trial = 0; trial < (points > 100000 ? 4 : 20); ++trial) {
      glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(unit(random), unit(random), unit(random)) * 1e6);
      m = glm::rotate(m, double(unit(random)) * 3.0, glm::normalize(glm::dvec3(unit(random), unit(random), 1.5)));
      m = glm::scale(m, glm::dvec3(unit(random) * 3.0, unit(random) + 2.0, 0.5));
      const Scene scene = singleMeshScene(mesh, m);
      const Bounds pruned = analyzeHierarchy(scene).worldBounds[0];
      Bounds brute;
      for (const glm::vec3& p : mesh.positions) {
        glm::dvec3 w;
        for (int axis = 0; axis < 3; ++axis)
          w[axis] = m[0][axis] * double(p.x) + m[1][axis] * double(p.y) + m[2][axis] * double(p.z) + m[3][axis];
        brute.extend(w);
      }
      EXPECT_EQ(pruned.min, brute.min) << points << " points, trial " << trial;
      EXPECT_EQ(pruned.max, brute.max) << points << " points, trial " << trial;
    }
  }
}

TEST(WorldBounds, FarFromTheOriginKeepsDoublePrecision) {
  const Scene scene = singleMeshScene(circleFan(4), glm::translate(glm::dmat4(1.0), {1e7, -1e7, 3e6}));
  const Hierarchy h = analyzeHierarchy(scene);
  EXPECT_EQ(h.worldBounds[0].min.x, 1e7 - 1.0);
  EXPECT_EQ(h.worldBounds[0].max.x, 1e7 + 1.0);
  EXPECT_EQ(h.worldBounds[0].min.z, 3e6);
}

TEST(Hierarchy, SubtreeTrianglesCountEveryInstance) {
  Scene scene = singleMeshScene(circleFan(8), glm::dmat4(1.0));
  // root → {a, b}; a → {instance 0, instance 1}; b → {instance 2}; all share mesh 0 (8 triangles).
  scene.nodes.clear();
  for (int i = 0; i < 3; ++i) {
    Node instance;
    instance.mesh = 0;
    instance.local = glm::translate(glm::dmat4(1.0), {3.0 * i, 0, 0});
    scene.nodes.push_back(instance);
  }
  Node a, b, root;
  a.children = {0, 1};
  b.children = {2};
  scene.nodes.push_back(a);  // 3
  scene.nodes.push_back(b);  // 4
  root.children = {3, 4};
  scene.nodes.push_back(root);  // 5
  scene.roots = {5};
  validateScene(scene, "instances");
  const Hierarchy h = analyzeHierarchy(scene);
  EXPECT_EQ(h.subtreeTriangles[5], 24u);
  EXPECT_EQ(h.subtreeTriangles[3], 16u);
  EXPECT_EQ(h.subtreeTriangles[4], 8u);
  EXPECT_EQ(h.preorder, (std::vector<std::uint32_t>{5, 3, 0, 1, 4, 2}));
  EXPECT_NEAR(h.worldBounds[5].max.x, 7.0, 1e-12);

  const SceneSummary s = summarizeScene(scene, h);
  EXPECT_EQ(s.nodes, 6u);
  EXPECT_EQ(s.meshes, 1u);
  EXPECT_EQ(s.instances, 3u);
  EXPECT_EQ(s.triangles, 24u);
  EXPECT_EQ(s.uniqueTriangles, 8u);
  EXPECT_EQ(s.maxDepth, 2u);

  EXPECT_EQ(nodesNeedingSurfels(h, 10), (std::vector<std::uint32_t>{5, 3}));
  EXPECT_TRUE(nodesNeedingSurfels(h, 24).empty());
}

TEST(Validation, CycleIsReportedWithTheNode) {
  Scene scene = singleMeshScene(circleFan(4), glm::dmat4(1.0));
  Node a, b;
  a.children = {2};
  b.children = {1};
  scene.nodes.push_back(a);  // 1
  scene.nodes.push_back(b);  // 2
  EXPECT_NE(validationMessage(scene).find("node 1: is not reachable"), std::string::npos) << validationMessage(scene);
}

TEST(Validation, TwoParentsAndBadReferences) {
  Scene scene = singleMeshScene(circleFan(4), glm::dmat4(1.0));
  Node a, b;
  a.children = {0};
  scene.nodes.push_back(a);
  scene.roots = {1, 0};
  EXPECT_NE(validationMessage(scene).find("node 0: has two parents"), std::string::npos) << validationMessage(scene);

  scene.roots = {1};
  scene.nodes[1].children = {7};
  EXPECT_NE(validationMessage(scene).find("node 1: child node 7 does not exist"), std::string::npos);

  scene.nodes[1].children = {0};
  scene.nodes[0].mesh = 3;
  EXPECT_NE(validationMessage(scene).find("node 0: mesh 3 does not exist"), std::string::npos);
}

TEST(Validation, NonFiniteDataIsRejected) {
  Scene scene = singleMeshScene(circleFan(4), glm::dmat4(1.0));
  EXPECT_EQ(validationMessage(scene), "");
  scene.nodes[0].local[3][1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(validationMessage(scene), "test.glb: node 0: transform is not finite");
  scene.nodes[0].local = glm::dmat4(1.0);
  scene.meshes[0].positions[2].y = std::numeric_limits<float>::infinity();
  EXPECT_EQ(validationMessage(scene), "test.glb: mesh 0: a position is not finite");
  scene.meshes[0].positions[2].y = 0;
  scene.meshes[0].indices[4] = 99;
  EXPECT_EQ(validationMessage(scene), "test.glb: mesh 0: index 99 out of range (5 vertices)");
}

TEST(Normals, AreaWeightedAndNeverNaN) {
  // Two triangles sharing vertex 0: a big one in XY (normal +Z) and a small one in XZ (normal +Y).
  const std::vector<glm::vec3> positions = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {1, 0, 0}, {0, 0, 1}, {5, 5, 5}};
  const std::vector<std::uint32_t> indices = {0, 1, 2, 0, 4, 3, 5, 5, 5};  // last one degenerate
  const auto normals = computeVertexNormals(positions, indices);
  const glm::dvec3 expected = glm::normalize(glm::dvec3(0, 0, 100) + glm::dvec3(0, 1, 0));
  EXPECT_NEAR(normals[0].z, expected.z, 1e-6);
  EXPECT_NEAR(normals[0].y, expected.y, 1e-6);
  EXPECT_EQ(normals[5], glm::vec3(0, 0, 1));  // only in a degenerate triangle: the defined fallback
  for (const glm::vec3& n : normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-6f);
}

}  // namespace
}  // namespace pbs

namespace pbs {
namespace {

// Names first (in preorder, so the first of two nodes named alike), then indices; nothing: the first root.
TEST(FindNode, ByNameThenIndexElseAnErrorNamingTheFile) {
  Scene scene = test::twoIdenticalGroups();
  scene.nodes[4].name = "3";  // a name that reads as another node's index
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  EXPECT_EQ(findNode(scene, hierarchy, "", "f.glb"), 0u);
  EXPECT_EQ(findNode(scene, hierarchy, "B", "f.glb"), 2u);
  EXPECT_EQ(findNode(scene, hierarchy, "left", "f.glb"), 3u);
  EXPECT_EQ(findNode(scene, hierarchy, "3", "f.glb"), 4u) << "the name wins over the index";
  EXPECT_EQ(findNode(scene, hierarchy, "5", "f.glb"), 5u);
  for (const char* missing : {"C", "7", "99999999999"}) {
    try {
      findNode(scene, hierarchy, missing, "f.glb");
      ADD_FAILURE() << missing;
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find("f.glb"), std::string::npos) << error.what();
      EXPECT_NE(std::string(error.what()).find(missing), std::string::npos) << error.what();
    }
  }
  Scene empty;
  EXPECT_THROW(findNode(empty, analyzeHierarchy(empty), "", "e.glb"), InputError);
}

}  // namespace
}  // namespace pbs
