// closedOutward: which meshes a view from outside sees by their front faces alone; meshClosure: which side
// a view from outside sees of a mesh closed but for its holes, and where those are.
#include "pbs/scene/mesh_closure.hpp"
#include "test_fixtures.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace pbs {
namespace {

// The cube [−1, 1]³ + offset, wound counter-clockwise seen from outside; with `splitFaces` each face has its
// own four vertices (as a mesh with a normal per face does), else the eight corners are shared.
Mesh cube(bool splitFaces, glm::vec3 offset = glm::vec3(0.0f)) {
  Mesh mesh;
  const auto corner = [&](int i) {
    return offset + glm::vec3(i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f);
  };
  if (!splitFaces)
    for (int i = 0; i < 8; ++i) mesh.positions.push_back(corner(i));
  // Each face's corners counter-clockwise from outside.
  const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& face : faces) {
    std::uint32_t v[4];
    for (int k = 0; k < 4; ++k) {
      if (splitFaces) {
        v[k] = std::uint32_t(mesh.positions.size());
        mesh.positions.push_back(corner(face[k]));
      } else {
        v[k] = std::uint32_t(face[k]);
      }
    }
    mesh.indices.insert(mesh.indices.end(), {v[0], v[1], v[2], v[0], v[2], v[3]});
  }
  mesh.parts.push_back(MeshPart{0, std::uint32_t(mesh.indices.size()), 0});
  updateMeshBounds(mesh);
  return mesh;
}

// Closed as it is, wound outward: a view from outside sees its front faces alone.
bool closedOutward(const Mesh& mesh) {
  const MeshClosure closure = meshClosure(mesh);
  return closure.facing == MeshFacing::closedOutward && closure.holes.empty();
}

// Every triangle turned over.
Mesh flipped(Mesh mesh) {
  for (std::size_t t = 0; t < mesh.indices.size(); t += 3) std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
  return mesh;
}

TEST(MeshClosure, ACubeWoundOutwardIsClosedWithSharedOrSplitCorners) {
  EXPECT_TRUE(closedOutward(cube(false)));
  EXPECT_TRUE(closedOutward(cube(true)));
}

TEST(MeshClosure, ACubeWoundInwardIsNot) {
  Mesh inward = cube(true);
  for (std::size_t t = 0; t < inward.indices.size(); t += 3) std::swap(inward.indices[t + 1], inward.indices[t + 2]);
  EXPECT_FALSE(closedOutward(inward));
}

TEST(MeshClosure, AMissingFaceOrAFaceWoundTheOtherWayOpensIt) {
  Mesh open = cube(false);
  open.indices.resize(open.indices.size() - 6);
  EXPECT_FALSE(closedOutward(open));
  Mesh oneFaceTurned = cube(false);
  std::swap(oneFaceTurned.indices[1], oneFaceTurned.indices[2]);
  std::swap(oneFaceTurned.indices[4], oneFaceTurned.indices[5]);
  EXPECT_FALSE(closedOutward(oneFaceTurned));
  // The fixture box winds three of its faces inward; a sheet has a border.
  EXPECT_FALSE(closedOutward(test::tessellatedBox(3)));
  EXPECT_FALSE(closedOutward(test::gridSheet(4, [](float, float) { return 0.0f; })));
}

// The faces a view from outside can see: a closed cube's front faces, the back faces of one wound inside
// out; a face wound the other way opens it.
TEST(MeshClosure, FacingTellsAClosedMeshWoundInsideOutApart) {
  Mesh mixed = cube(false);
  std::swap(mixed.indices[1], mixed.indices[2]);
  std::swap(mixed.indices[4], mixed.indices[5]);
  for (const bool split : {false, true}) {
    EXPECT_EQ(meshClosure(cube(split)).facing, MeshFacing::closedOutward);
    EXPECT_TRUE(meshClosure(cube(split)).holes.empty());
    EXPECT_EQ(meshClosure(flipped(cube(split))).facing, MeshFacing::closedInward);
  }
  EXPECT_EQ(meshClosure(flipped(cube(true, glm::vec3(3.0e6f, -2.0e6f, 1.0e6f)))).facing, MeshFacing::closedInward);
  for (const Mesh& mesh : {mixed, flipped(mixed), Mesh{}}) EXPECT_EQ(meshClosure(mesh).facing, MeshFacing::open);
  Mesh nan = flipped(cube(false));
  nan.positions[3].y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(meshClosure(nan).facing, MeshFacing::open);
}

// A missing face is a hole: the cube is closed once it is capped, each way round, the hole's box that face's
// square; two missing faces apart are two holes, and two that share an edge one. A flat sheet encloses nothing
// once capped, so it stays open; a bump gives it a volume and its whole rim is the hole.
TEST(MeshClosure, HolesAreTheBoundarysConnectedParts) {
  const auto without = [](Mesh mesh, std::initializer_list<int> faces) {
    std::vector<std::uint32_t> kept;
    for (std::size_t f = 0; f < 6; ++f)
      if (std::find(faces.begin(), faces.end(), int(f)) == faces.end())
        kept.insert(kept.end(), mesh.indices.begin() + 6 * f, mesh.indices.begin() + 6 * f + 6);
    mesh.indices = kept;
    mesh.parts[0].indexCount = std::uint32_t(kept.size());
    return mesh;
  };
  for (const bool split : {false, true}) {
    const MeshClosure open = meshClosure(without(cube(split), {0}));  // the face x = −1
    EXPECT_EQ(open.facing, MeshFacing::closedOutward);
    ASSERT_EQ(open.holes.size(), 1u);
    EXPECT_EQ(open.holes[0].min, glm::dvec3(-1.0, -1.0, -1.0));
    EXPECT_EQ(open.holes[0].max, glm::dvec3(-1.0, 1.0, 1.0));
    EXPECT_EQ(meshClosure(flipped(without(cube(split), {0}))).facing, MeshFacing::closedInward);
    EXPECT_EQ(meshClosure(without(cube(split), {0, 1})).holes.size(), 2u);  // x = −1 and x = +1
  }
  EXPECT_EQ(meshClosure(without(cube(false), {0, 2})).holes.size(), 1u);  // x = −1 and y = −1 share an edge
  EXPECT_EQ(meshClosure(test::gridSheet(4, [](float, float) { return 0.0f; })).facing, MeshFacing::open);
  const MeshClosure bump = meshClosure(test::gridSheet(4, [](float x, float y) { return 1.0f - x * x - y * y; }));
  EXPECT_NE(bump.facing, MeshFacing::open);
  ASSERT_EQ(bump.holes.size(), 1u);
  EXPECT_EQ(bump.holes[0].min.x, -1.0);
  EXPECT_EQ(bump.holes[0].max.y, 1.0);
}

// A scene's closures, one per mesh in order; a mesh not loaded (no arrays) is drawn from both sides.
TEST(MeshClosure, ASceneGivesEachMeshItsClosure) {
  Scene scene;
  Mesh unloaded = cube(false);
  unloaded.positions.clear();
  unloaded.indices.clear();
  scene.meshes = {cube(false), flipped(cube(true)), unloaded};
  const std::vector<MeshClosure> closures = meshClosures(scene);
  ASSERT_EQ(closures.size(), 3u);
  EXPECT_EQ(closures[0].facing, MeshFacing::closedOutward);
  EXPECT_EQ(closures[1].facing, MeshFacing::closedInward);
  EXPECT_EQ(closures[2].facing, MeshFacing::open);
}

TEST(MeshClosure, AnEdgeRunTwiceTheSameWayIsNotClosed) {
  Mesh doubled = cube(false);
  const std::vector<std::uint32_t> first(doubled.indices.begin(), doubled.indices.begin() + 3);
  doubled.indices.insert(doubled.indices.end(), first.begin(), first.end());
  EXPECT_FALSE(closedOutward(doubled));
}

TEST(MeshClosure, TrianglesWithoutAreaAreLeftOut) {
  Mesh withDegenerate = cube(false);
  withDegenerate.indices.insert(withDegenerate.indices.end(), {0, 0, 5});
  EXPECT_TRUE(closedOutward(withDegenerate));
}

TEST(MeshClosure, FarFromTheOriginAndTiny) {
  EXPECT_TRUE(closedOutward(cube(true, glm::vec3(3.0e6f, -2.0e6f, 1.0e6f))));
  Mesh tiny = cube(false);
  for (glm::vec3& p : tiny.positions) p *= 1e-20f;
  EXPECT_TRUE(closedOutward(tiny));
  // A hole far from the origin, and a tiny one, keep their volume's sign.
  Mesh farOpen = cube(true, glm::vec3(3.0e6f, -2.0e6f, 1.0e6f)), tinyOpen = cube(true);
  for (glm::vec3& p : tinyOpen.positions) p *= 1e-20f;
  for (Mesh* mesh : {&farOpen, &tinyOpen}) {
    mesh->indices.resize(mesh->indices.size() - 6);
    mesh->parts[0].indexCount = std::uint32_t(mesh->indices.size());
    const MeshClosure closure = meshClosure(*mesh);
    EXPECT_EQ(closure.facing, MeshFacing::closedOutward);
    EXPECT_EQ(closure.holes.size(), 1u);
    EXPECT_EQ(meshClosure(flipped(*mesh)).facing, MeshFacing::closedInward);
  }
}

TEST(MeshClosure, BadInputIsNotClosed) {
  EXPECT_FALSE(closedOutward(Mesh{}));
  Mesh nan = cube(false);
  nan.positions[3].y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(closedOutward(nan));
  Mesh infinite = cube(false);
  infinite.positions[2].x = std::numeric_limits<float>::infinity();
  EXPECT_FALSE(closedOutward(infinite));
  Mesh outOfRange = cube(false);
  outOfRange.indices[7] = 99;
  EXPECT_FALSE(closedOutward(outOfRange));
  for (const Mesh& mesh : {Mesh{}, nan, infinite, outOfRange}) EXPECT_EQ(meshClosure(mesh).facing, MeshFacing::open);
}

}  // namespace
}  // namespace pbs
