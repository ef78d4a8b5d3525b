// Simplified meshes, the alternative to surfels: the triangle budget is kept, nothing grows, vertices
// stay within the original bounds with their attributes, any thread count gives the same meshes, bad
// input passes through untouched; and rendered in place of surfels they give the exact image at ratio 1.
#include "test_fixtures.hpp"

#include <pbs/raster/headlight_shading.hpp>
#include <pbs/raster/orbit_camera.hpp>
#include <pbs/raster/thread_arena.hpp>
#include <pbs/scene/scene_draws.hpp>
#include <pbs/scene/simplified_meshes.hpp>
#include <pbs/surfels/simplified_lod.hpp>
#include <pbs/surfels/surfelize.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

namespace pbs {
namespace {

using test::tessellatedBox;

// A welded, curved n×n grid of 2·n² triangles with uvs, one part: nothing stops meshoptimizer short
// of a target but the error bound (tessellatedBox's faces meet at seams that hold it back).
Mesh wavyGrid(std::uint32_t n) {
  Mesh mesh = test::gridSheet(n, [](float x, float y) { return 0.2f * std::sin(3.0f * x) * std::cos(2.0f * y); });
  for (const glm::vec3& p : mesh.positions) mesh.uvs.emplace_back(0.5f * (p.x + 1.0f), 0.5f * (p.y + 1.0f));
  return mesh;
}

// tessellatedBox(n) with uvs.
Mesh texturedBox(std::uint32_t n) {
  Mesh mesh = tessellatedBox(n);
  for (const glm::vec3& p : mesh.positions) mesh.uvs.emplace_back(0.5f * (p.x + 1.0f), 0.5f * (p.y + 1.0f));
  return mesh;
}

// texturedBox(n) with its triangles split into two parts of different materials.
Mesh twoPartBox(std::uint32_t n) {
  Mesh mesh = texturedBox(n);
  const auto half = std::uint32_t(mesh.indices.size() / 6 * 3);
  mesh.parts = {MeshPart{0, half, 1}, MeshPart{half, std::uint32_t(mesh.indices.size()) - half, 0}};
  return mesh;
}

SimplifyOptions ratioOf(double ratio, double targetError = 1.0) {
  SimplifyOptions options;
  options.ratio = ratio;
  options.targetError = targetError;
  return options;
}

// Every index in range, one normal and uv per position, parts covering the indices in whole triangles.
void expectWellFormed(const Mesh& mesh) {
  for (std::uint32_t i : mesh.indices) ASSERT_LT(i, mesh.positions.size());
  EXPECT_EQ(mesh.normals.size(), mesh.positions.size());
  EXPECT_TRUE(mesh.uvs.empty() || mesh.uvs.size() == mesh.positions.size());
  test::expectPartsCoverIndices(mesh);
}

TEST(SimplifyMesh, KeepsAtMostTheRatioAndNeverGrows) {
  const Mesh grid = wavyGrid(50);  // 5,000 triangles
  std::uint64_t previous = grid.triangleCount();
  for (double ratio : {0.5, 0.25, 0.05, 0.01}) {
    const SimplifiedMesh simplified = simplifyMesh(grid, ratioOf(ratio));
    const Mesh& mesh = simplified.mesh;
    expectWellFormed(mesh);
    // The target is rounded to whole triangles: at most half a triangle over.
    EXPECT_LE(double(mesh.triangleCount()), ratio * double(grid.triangleCount()) + 0.5) << ratio;
    EXPECT_GT(mesh.triangleCount(), 0u) << ratio;
    EXPECT_LE(mesh.triangleCount(), previous) << "a smaller ratio never keeps more: " << ratio;
    EXPECT_LT(mesh.positions.size(), grid.positions.size()) << "unused vertices are dropped: " << ratio;
    previous = mesh.triangleCount();
  }
}

TEST(SimplifyMesh, VerticesStayInsideTheBoundsWithTheirAttributesAndParts) {
  const Mesh box = twoPartBox(16);
  const Mesh mesh = simplifyMesh(box, ratioOf(0.1)).mesh;
  expectWellFormed(mesh);
  EXPECT_LT(mesh.triangleCount(), box.triangleCount() / 2);
  ASSERT_EQ(mesh.parts.size(), 2u);
  EXPECT_EQ(mesh.parts[0].material, 1u);
  EXPECT_EQ(mesh.parts[1].material, 0u);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_GE(mesh.bounds.min[axis], box.bounds.min[axis]);
    EXPECT_LE(mesh.bounds.max[axis], box.bounds.max[axis]);
  }
  // meshopt_simplify only picks vertices of the input, so each kept vertex carries its own normal and uv.
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    bool found = false;
    for (std::size_t w = 0; w < box.positions.size() && !found; ++w)
      found = box.positions[w] == mesh.positions[v] && box.normals[w] == mesh.normals[v] && box.uvs[w] == mesh.uvs[v];
    EXPECT_TRUE(found) << v;
  }
}

TEST(SimplifyMesh, NoCrackOpensWhereTwoPartsMeet) {
  // The grid's lower and upper halves as two parts sharing the middle row of vertices: every vertex of
  // that row must still be used by both parts, or a crack would show between the materials.
  const std::uint32_t n = 40;
  Mesh grid = wavyGrid(n);
  const auto half = std::uint32_t(grid.indices.size() / 2);
  grid.parts = {MeshPart{0, half, 0}, MeshPart{half, std::uint32_t(grid.indices.size()) - half, 0}};
  const Mesh mesh = simplifyMesh(grid, ratioOf(0.01)).mesh;
  ASSERT_EQ(mesh.parts.size(), 2u);
  EXPECT_LT(mesh.triangleCount(), grid.triangleCount() / 4);
  const float middle = grid.positions[(n / 2) * (n + 1)].y;
  for (const MeshPart& part : mesh.parts) {
    std::set<float> xs;
    for (std::uint32_t i = part.firstIndex; i < part.firstIndex + part.indexCount; ++i)
      if (mesh.positions[mesh.indices[i]].y == middle) xs.insert(mesh.positions[mesh.indices[i]].x);
    EXPECT_EQ(xs.size(), n + 1) << "part at " << part.firstIndex;
  }
}

TEST(SimplifyMesh, TheErrorBoundStopsShortOfTheRatio) {
  // A curved surface has few collapses without error: a tight bound keeps more triangles.
  const Mesh wavy = wavyGrid(40);
  const SimplifiedMesh tight = simplifyMesh(wavy, ratioOf(0.01, 1e-3));
  const SimplifiedMesh loose = simplifyMesh(wavy, ratioOf(0.01, 1.0));
  EXPECT_GT(tight.mesh.triangleCount(), loose.mesh.triangleCount());
  EXPECT_LE(tight.error, 1e-3f);
  EXPECT_GT(loose.error, tight.error);
}

TEST(SimplifyMesh, RatioOneAndUnsimplifiableMeshesComeBackUnchanged) {
  const Mesh box = twoPartBox(4);
  EXPECT_EQ(simplifyMesh(box, ratioOf(1.0)).mesh.indices, box.indices);

  Mesh empty;
  const SimplifiedMesh none = simplifyMesh(empty, ratioOf(0.5));
  EXPECT_TRUE(none.mesh.indices.empty());
  EXPECT_TRUE(none.mesh.positions.empty());

  Mesh nan = box;
  nan.positions[3].y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(simplifyMesh(nan, ratioOf(0.5)).mesh.indices, nan.indices);

  Mesh outOfRange = box;
  outOfRange.indices[5] = std::uint32_t(box.positions.size());
  EXPECT_EQ(simplifyMesh(outOfRange, ratioOf(0.5)).mesh.indices, outOfRange.indices);

  Mesh uncovered = box;
  uncovered.parts.pop_back();
  EXPECT_EQ(simplifyMesh(uncovered, ratioOf(0.5)).mesh.indices, uncovered.indices);

  for (double bad : {0.0, -0.5, 1.5, std::numeric_limits<double>::quiet_NaN()})
    EXPECT_THROW(simplifyMesh(box, ratioOf(bad)), std::invalid_argument) << bad;
}

// Three different meshes, each drawn once, two of them with two parts.
Scene threeMeshes() {
  Scene scene = test::sceneOf(twoPartBox(12), {glm::dmat4(1.0)});
  scene.meshes.push_back(twoPartBox(20));
  scene.meshes.push_back(tessellatedBox(9));
  for (std::int32_t m = 1; m < 3; ++m) {
    scene.roots.push_back(std::uint32_t(scene.nodes.size()));
    scene.nodes.push_back(Node{"node", test::placed({3.0 * m, 0, 0}, 0.2 * m, glm::dvec3(1.0)), {}, m});
  }
  validateScene(scene, "three meshes");
  return scene;
}

TEST(SimplifyScene, SameMeshesForAnyThreadCountAndTheSameNodes) {
  const Scene scene = threeMeshes();
  SimplifiedScene one, two, four;
  runWithThreads(1, [&] { one = simplifyScene(scene, ratioOf(0.2, 1e-2)); });
  runWithThreads(2, [&] { two = simplifyScene(scene, ratioOf(0.2, 1e-2)); });
  runWithThreads(4, [&] { four = simplifyScene(scene, ratioOf(0.2, 1e-2)); });
  ASSERT_EQ(one.scene.meshes.size(), scene.meshes.size());
  for (const SimplifiedScene* other : {&two, &four})
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
      EXPECT_EQ(other->scene.meshes[m].indices, one.scene.meshes[m].indices) << m;
      EXPECT_EQ(other->scene.meshes[m].positions, one.scene.meshes[m].positions) << m;
    }
  EXPECT_NO_THROW(validateScene(one.scene, "simplified"));
  EXPECT_EQ(one.scene.nodes.size(), scene.nodes.size());
  EXPECT_EQ(one.scene.roots, scene.roots);
  EXPECT_EQ(one.trianglesBefore, 1728u + 4800u + 972u);  // 12·n² triangles each
  EXPECT_LT(one.trianglesAfter, one.trianglesBefore);
  EXPECT_LE(one.largestError, 1e-2f);
}

// A scene of two groups of boxes with surfels (small, fast settings), as the LOD tests make it.
struct LodScene {
  Scene scene;
  Hierarchy hierarchy;
  SceneSurfels surfels;
};

LodScene lodScene() {
  LodScene s{test::twoIdenticalGroups(), {}, {}};
  s.hierarchy = analyzeHierarchy(s.scene);
  SurfelizeOptions options;
  options.file.threshold = 1000;
  options.file.maxSurfels = 4000;
  options.file.resolution = 128;
  s.surfels = sceneSurfelsOf(surfelize(s.scene, s.hierarchy, options), s.scene, s.hierarchy, "test");
  return s;
}

Camera orbitAround(const LodScene& s, double distance) {
  const Bounds& box = s.hierarchy.worldBounds[s.scene.roots.front()];
  return orbitCamera(box.center(), 0.5 * glm::length(box.size()), Orbit{30.0, 20.0, distance}, 256, 256);
}

std::vector<glm::vec4> exactImage(const LodScene& s, const Camera& camera) {
  Framebuffer gbuffer = makeFramebuffer(camera.width, camera.height, kChannelColor | kChannelNormal);
  drawSceneTriangles(s.scene, s.hierarchy, camera, gbuffer, TriangleOptions{.cullBackFaces = false});
  return shadeHeadlight(gbuffer, camera);
}

std::vector<glm::vec4> simplifiedImage(const LodScene& s, const Scene& simplified, const SceneSurfels& surfels,
                                       const Camera& camera, LodStats* stats = nullptr) {
  Framebuffer gbuffer = makeFramebuffer(camera.width, camera.height, kChannelColor | kChannelNormal);
  const LodStats drawn = renderSimplifiedLod(s.scene, simplified, s.hierarchy, surfels, camera, gbuffer, LodOptions{});
  if (stats) *stats = drawn;
  return shadeHeadlight(gbuffer, camera);
}

TEST(SimplifiedLod, WithoutSurfelsItIsTheExactRendering) {
  const LodScene s = lodScene();
  const Scene simplified = simplifyScene(s.scene, ratioOf(0.1)).scene;
  const Camera camera = orbitAround(s, 40.0);
  LodStats stats;
  EXPECT_EQ(simplifiedImage(s, simplified, SceneSurfels{}, camera, &stats), exactImage(s, camera))
      << "no node has surfels, so none is drawn simplified";
  EXPECT_EQ(stats.nodesSurfels, 0u);
}

TEST(SimplifiedLod, AtRatioOneItIsTheExactRenderingAtAnyDistance) {
  // Swapping every surfel draw for its whole subtree's triangles draws each visible mesh exactly once.
  const LodScene s = lodScene();
  const Scene whole = simplifyScene(s.scene, ratioOf(1.0)).scene;
  std::uint64_t simplifiedNodes = 0;
  for (double distance : {2.0, 3.0, 8.0, 40.0, 200.0}) {
    const Camera camera = orbitAround(s, distance);
    LodStats stats;
    EXPECT_EQ(simplifiedImage(s, whole, s.surfels, camera, &stats), exactImage(s, camera)) << distance;
    EXPECT_EQ(stats.surfels, 0u);
    simplifiedNodes += stats.nodesSurfels;
  }
  EXPECT_GT(simplifiedNodes, 0u) << "some view must draw a node in place of its surfels";
}

TEST(SimplifiedLod, FarAwayFewerTrianglesAndTheSameImageForAnyThreadCount) {
  const LodScene s = lodScene();
  const Scene simplified = simplifyScene(s.scene, ratioOf(0.25)).scene;
  const Camera camera = orbitAround(s, 40.0);
  std::vector<glm::vec4> one, two, four;
  LodStats stats;
  runWithThreads(1, [&] { one = simplifiedImage(s, simplified, s.surfels, camera, &stats); });
  runWithThreads(2, [&] { two = simplifiedImage(s, simplified, s.surfels, camera); });
  runWithThreads(4, [&] { four = simplifiedImage(s, simplified, s.surfels, camera); });
  EXPECT_EQ(one, two);
  EXPECT_EQ(one, four);
  EXPECT_GT(stats.nodesSurfels, 0u);
  EXPECT_GT(stats.triangles, 0u);
  EXPECT_LE(double(stats.triangles), 0.25 * 4.0 * double(s.scene.meshes[0].triangleCount()) + 4.0);
  EXPECT_TRUE(std::any_of(one.begin(), one.end(), [](const glm::vec4& p) { return p.a > 0.5f; }));
}

}  // namespace
}  // namespace pbs
