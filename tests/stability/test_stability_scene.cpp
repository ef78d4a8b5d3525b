// Numerical stability of the scene layer: glTF import of stiff and non-finite files (written to a temp
// dir), the hierarchy's transforms and bounds, and the Embree ray caster at the edges.
#include "stability_checks.hpp"

#include "gltf_test_files.hpp"
#include "test_fixtures.hpp"
#include "test_support.hpp"

#include <pbs/scene/embree_caster.hpp>
#include <pbs/scene/gltf_import.hpp>
#include <pbs/scene/hierarchy.hpp>
#include <pbs/scene/input_error.hpp>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace pbs {
namespace {

using stability::expectFiniteFramebuffer;
using stability::framebufferBytes;
using stability::sameBytesForOneTwoAndFourThreads;
using test::GltfBuilder;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// Writes `builder` to `dir` as .glb and imports it from disk; the InputError's text, or "" on success.
std::string importError(const GltfBuilder& builder, const test::ScratchDir& dir, ImportResult* result = nullptr) {
  const std::filesystem::path file = dir / "stiff.glb";
  test::writeFile(file, builder.glb());
  try {
    ImportResult imported = importGltf(file);
    validateScene(imported.scene, file.string());
    if (result) *result = std::move(imported);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

// The triangle file with a float attribute `semantic` of `components` per vertex whose vertex 1 holds `bad`.
GltfBuilder triangleWithAttribute(const std::string& semantic, int components, float bad) {
  GltfBuilder b = test::triangleFile();
  std::vector<float> values(std::size_t(3 * components), 0.0f);
  values[std::size_t(components - 1)] = 1.0f;
  values[std::size_t(2 * components - 1)] = 1.0f;
  values[std::size_t(components)] = bad;  // vertex 1's first component
  const int accessor = b.addAccessor(values, test::kFloat, components == 2 ? "VEC2" : "VEC3");
  b.json["meshes"][0]["primitives"][0]["attributes"][semantic] = accessor;
  return b;
}

// Expected: a NaN or Inf in any float attribute (positions are BadData.NanAndInfPositions) is an
// InputError naming the file, the accessor and the element, never a scene with NaN in it.
TEST(StabilityScene, NonFiniteNormalsAndUvsInAGlbAreInputErrors) {
  test::ScratchDir dir;
  for (const float bad : {kNaN, kInf, -kInf}) {
    for (const auto& [semantic, components] : {std::pair{"NORMAL", 3}, std::pair{"TEXCOORD_0", 2}}) {
      SCOPED_TRACE(testing::Message() << semantic << " " << bad);
      const std::string error = importError(triangleWithAttribute(semantic, components, bad), dir);
      EXPECT_TRUE(error.starts_with((dir / "stiff.glb").string() + ": accessor 2: element 1 is not finite")) << error;
    }
  }
}

// Expected: node transforms whose product overflows (each finite: scale 1e200 under scale 1e200) are
// an InputError naming the node, since the world transform and every bound below it would be Inf.
TEST(StabilityScene, NodeTransformsWhoseProductOverflowsAreInputErrors) {
  test::ScratchDir dir;
  GltfBuilder b = test::triangleFile();
  b.json["nodes"][0].erase("mesh");  // only the child's world overflows, not a mesh under the parent
  b.json["nodes"][0]["scale"] = {1e200, 1e200, 1e200};
  b.json["nodes"][0]["children"] = {1};
  b.addNode({{"mesh", 0}, {"scale", {1e200, 1e200, 1e200}}});
  const std::string error = importError(b, dir);
  EXPECT_TRUE(error.starts_with((dir / "stiff.glb").string() + ": node 1: ")) << error;
  EXPECT_NE(error.find("not finite"), std::string::npos) << error;
}

// Expected: vertices near float's largest value are accepted where they stay in range and refused,
// naming the node, where a world scale pushes them past it: pbs stores and draws in float, so such a
// coordinate would reach the outputs as Inf.
TEST(StabilityScene, MeshesPushedPastFloatRangeAreInputErrors) {
  Mesh mesh = test::tessellatedBox(1);
  for (glm::vec3& p : mesh.positions) p *= 3e38f;
  updateMeshBounds(mesh);
  EXPECT_NO_THROW(test::sceneOf(mesh, {glm::dmat4(1.0)}));
  try {
    test::sceneOf(mesh, {glm::dmat4(1.0), glm::scale(glm::dmat4(1.0), glm::dvec3(2.0))});
    ADD_FAILURE() << "a world coordinate of 6e38 was accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("node 1: its mesh reaches past float's range"), std::string::npos)
        << error.what();
  }
}

// Expected: a glTF mesh whose only primitive draws no triangles (POINTS) is not imported and its node
// carries no mesh; a scene model with a mesh of vertices but no indices gives its node an empty box and
// no triangles; the ray caster builds on it and misses everywhere. (`pbs` refuses a scene with nothing
// to draw at all: StabilityCli.SceneWithNoTrianglesIsOneErrorLine.)
TEST(StabilityScene, MeshWithNoTrianglesHasEmptyBoundsAndRendersNothing) {
  test::ScratchDir dir;
  GltfBuilder b = test::triangleFile();
  b.json["meshes"][0]["primitives"][0]["mode"] = test::kModePoints;
  ImportResult imported;
  ASSERT_EQ(importError(b, dir, &imported), "");
  EXPECT_TRUE(imported.scene.meshes.empty());
  EXPECT_EQ(imported.scene.nodes.at(0).mesh, -1);

  Mesh empty;
  empty.positions = {{0, 0, 0}, {1, 2, 3}};
  empty.normals = computeVertexNormals(empty.positions, empty.indices);
  updateMeshBounds(empty);
  const Scene scene = test::sceneOf(empty, {glm::dmat4(1.0)});
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  EXPECT_EQ(hierarchy.subtreeTriangles[0], 0u);
  const SceneSummary summary = summarizeScene(scene, hierarchy);
  EXPECT_EQ(summary.triangles, 0u);
  const EmbreeScene embree(scene, hierarchy);
  EXPECT_TRUE(stability::finite(glm::vec3(embree.origin())));
  const Camera camera = perspectiveCamera(glm::dmat4(1.0), 1.0, 0.1, 10.0, 8, 8);
  Framebuffer framebuffer = makeFramebuffer(8, 8, kChannelPosition | kChannelNormal | kChannelIds);
  embree.render(camera, framebuffer);
  expectFiniteFramebuffer(framebuffer);
  EXPECT_TRUE(test::coveredPixels(framebuffer).empty());
}

// Expected: duplicated vertices (every position twice, the triangle repeated on the copies) import as
// given; normals computed over them are unit length, never NaN; bounds are those of the triangle.
TEST(StabilityScene, DuplicatedVerticesAndTrianglesImportWithUnitNormals) {
  test::ScratchDir dir;
  GltfBuilder b;
  const int positions =
      b.addAccessor(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0}, test::kFloat, "VEC3");
  const int indices =
      b.addAccessor(std::vector<std::uint16_t>{0, 1, 2, 3, 4, 5, 0, 4, 2, 0, 0, 0}, test::kUnsignedShort, "SCALAR");
  b.addMesh({{{"attributes", {{"POSITION", positions}}}, {"indices", indices}}});
  b.addNode({{"mesh", 0}});
  b.setScene({0});
  ImportResult imported;
  ASSERT_EQ(importError(b, dir, &imported), "");
  const Mesh& mesh = imported.scene.meshes.at(0);
  EXPECT_EQ(mesh.triangleCount(), 4u);
  for (const glm::vec3& n : mesh.normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-6f);
  EXPECT_EQ(mesh.bounds.min, glm::dvec3(0.0));
  EXPECT_EQ(mesh.bounds.max, glm::dvec3(1.0, 1.0, 0.0));
}

// ---- Hierarchy --------------------------------------------------------------------------------

// Expected: a node 1e7 from the origin under a parent that moves it back keeps exact bounds, and
// analyzeSubtree of a far or scaled node sees its subtree in its own frame, the same box as at the
// origin: bit for bit, since the node's own transform is left out.
TEST(StabilityScene, FarAndScaledNodesHaveExactBoundsInTheirOwnFrame) {
  const Mesh box = test::tessellatedBox(2);
  for (const auto& [offset, scale] : {std::pair{glm::dvec3(1e7, -1e7, 1e6), 1.0}, std::pair{glm::dvec3(0.0), 1e-6},
                                      std::pair{glm::dvec3(0.0), 1e6}}) {
    Scene scene = test::sceneOf(box, {glm::scale(glm::translate(glm::dmat4(1.0), offset), glm::dvec3(scale))});
    const Hierarchy world = analyzeHierarchy(scene);
    EXPECT_EQ(world.worldBounds[0].min, offset - glm::dvec3(scale));
    EXPECT_EQ(world.worldBounds[0].max, offset + glm::dvec3(scale));
    const Hierarchy own = analyzeSubtree(scene, 0);
    EXPECT_EQ(own.worldBounds[0].min, glm::dvec3(-1.0));
    EXPECT_EQ(own.worldBounds[0].max, glm::dvec3(1.0));
  }
  // Offsets that cancel: +1e7 then −1e7 + 0.5 leave the child at exactly 0.5.
  Scene scene = test::sceneOf(box, {});
  scene.nodes = {Node{"parent", glm::translate(glm::dmat4(1.0), glm::dvec3(1e7, 0.0, 0.0)), {1}, -1},
                 Node{"child", glm::translate(glm::dmat4(1.0), glm::dvec3(-1e7 + 0.5, 0.0, 0.0)), {}, 0}};
  scene.roots = {0};
  validateScene(scene, "cancel");
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  EXPECT_EQ(hierarchy.worldBounds[0].min.x, -0.5);
  EXPECT_EQ(hierarchy.worldBounds[0].max.x, 1.5);
}

// Expected: a zero-thickness node (a flat quad) and a node of one triangle have boxes that are flat,
// not empty, with one triangle counted.
TEST(StabilityScene, ZeroThicknessAndOneTriangleNodesHaveFlatBoxes) {
  Mesh triangle;
  triangle.positions = {{0, 0, 2}, {1, 0, 2}, {0, 1, 2}};
  triangle.indices = {0, 1, 2};
  triangle.normals = computeVertexNormals(triangle.positions, triangle.indices);
  triangle.parts = {MeshPart{0, 3, 0}};
  updateMeshBounds(triangle);
  const Scene scene = test::sceneOf(triangle, {glm::dmat4(1.0)});
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  EXPECT_FALSE(hierarchy.worldBounds[0].empty());
  EXPECT_EQ(hierarchy.worldBounds[0].size(), glm::dvec3(1.0, 1.0, 0.0));
  EXPECT_EQ(hierarchy.subtreeTriangles[0], 1u);
}

// ---- Embree ray caster ------------------------------------------------------------------------

// A 2×2 box seen from `eye` (relative to its centre), all of it placed at `offset` and scaled.
struct CastView {
  Scene scene;
  Hierarchy hierarchy;
  Camera camera;
};

CastView castView(const glm::dvec3& offset, double scale, const glm::dvec3& eye, double near, double far) {
  CastView v;
  v.scene =
      test::sceneOf(test::tessellatedBox(4), {glm::scale(glm::translate(glm::dmat4(1.0), offset), glm::dvec3(scale))});
  v.hierarchy = analyzeHierarchy(v.scene);
  const glm::dmat4 view = glm::lookAt(offset + scale * eye, offset, glm::dvec3(0.0, 1.0, 0.0));
  v.camera = perspectiveCamera(view, glm::radians(60.0), near * scale, far * scale, 64, 48);
  return v;
}

Framebuffer cast(const CastView& v, const glm::dvec3& positionOrigin) {
  const EmbreeScene embree(v.scene, v.hierarchy);
  Framebuffer framebuffer =
      makeFramebuffer(v.camera.width, v.camera.height, kChannelPosition | kChannelNormal | kChannelIds, positionOrigin);
  embree.render(v.camera, framebuffer);
  return framebuffer;
}

// Expected: offsets of 1e6 and 1e7 and scales of 1e-6 and 1e6 give the unit scene's image: Embree
// works in float relative to origin(), so only pixels whose rays graze an edge may differ. Measured:
// no pixel differs, depth within 6e-8 (asserted: ≤ 2 pixels differ, depth within 1e-6).
TEST(StabilityScene, EmbreeFarOrScaledSceneMatchesTheUnitScene) {
  const glm::dvec3 eye(2.0, 1.5, 3.5);
  const Framebuffer unit = cast(castView(glm::dvec3(0.0), 1.0, eye, 0.5, 20.0), glm::dvec3(0.0));
  ASSERT_GT(test::coveredPixels(unit).size(), 500u);
  std::size_t mostDiffering = 0;
  double depthError = 0.0;
  for (const auto& [offset, scale] :
       {std::pair{glm::dvec3(1e6, 1e6, -1e6), 1.0}, std::pair{glm::dvec3(1e7, -1e7, 0.0), 1.0},
        std::pair{glm::dvec3(0.0), 1e-6}, std::pair{glm::dvec3(0.0), 1e6}}) {
    SCOPED_TRACE(testing::Message() << "offset " << offset.x << " scale " << scale);
    const CastView view = castView(offset, scale, eye, 0.5, 20.0);
    const Framebuffer moved =
        sameBytesForOneTwoAndFourThreads([&, &at = offset] { return cast(view, at); }, framebufferBytes);
    expectFiniteFramebuffer(moved);
    std::size_t differ = 0;
    for (std::size_t p = 0; p < unit.pixelCount(); ++p) {
      if (unit.covered(p) != moved.covered(p))
        ++differ;
      else if (unit.covered(p))
        depthError = std::max(depthError, double(std::abs(unit.depth[p] - moved.depth[p])));
    }
    EXPECT_LE(differ, 2u);
    mostDiffering = std::max(mostDiffering, differ);
  }
  stability::recordMeasured("max_differing_pixels", double(mostDiffering));
  stability::recordMeasured("max_depth_error", depthError);
  EXPECT_LE(depthError, 1e-6);
}

// Expected: a camera inside the box sees its inside walls on every pixel (faces are never culled);
// with near 1e-6 and far 1e9 too; a NaN or Inf camera casts no ray and leaves every pixel cleared.
TEST(StabilityScene, EmbreeCameraInsideTheBoxAndNonFiniteCameras) {
  for (const auto& [near, far] : {std::pair{0.01, 10.0}, std::pair{1e-6, 1e9}}) {
    const CastView inside = castView(glm::dvec3(1e6), 1.0, glm::dvec3(0.1, 0.2, 0.3), near, far);
    const Framebuffer framebuffer = cast(inside, glm::dvec3(1e6));
    expectFiniteFramebuffer(framebuffer);
    EXPECT_EQ(test::coveredPixels(framebuffer).size(), 64u * 48u) << "near " << near;
  }
  CastView view = castView(glm::dvec3(0.0), 1.0, glm::dvec3(2.0, 1.5, 3.5), 0.5, 20.0);
  for (const double bad : {double(kNaN), double(kInf)}) {
    view.camera.view[3][0] = bad;
    const Framebuffer framebuffer = cast(view, glm::dvec3(0.0));
    expectFiniteFramebuffer(framebuffer);
    EXPECT_TRUE(test::coveredPixels(framebuffer).empty());
  }
}

}  // namespace
}  // namespace pbs
