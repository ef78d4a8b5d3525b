// closedOutward: which meshes a view from outside sees by their front faces alone; meshFacing: which side
// of the others faces out.
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
  Mesh flipped = cube(false);
  std::swap(flipped.indices[1], flipped.indices[2]);
  std::swap(flipped.indices[4], flipped.indices[5]);
  EXPECT_FALSE(closedOutward(flipped));
  // The fixture box winds three of its faces inward; a sheet has a border.
  EXPECT_FALSE(closedOutward(test::tessellatedBox(3)));
  EXPECT_FALSE(closedOutward(test::gridSheet(4, [](float, float) { return 0.0f; })));
}

// The faces a view from outside can see: a closed cube's front faces, the back faces of one wound inside
// out (a cube with a face wound the other way, or one missing, is open either way round).
TEST(MeshClosure, FacingTellsAClosedMeshWoundInsideOutApart) {
  const auto flip = [](Mesh mesh) {
    for (std::size_t t = 0; t < mesh.indices.size(); t += 3) std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
    return mesh;
  };
  Mesh open = cube(false);
  open.indices.resize(open.indices.size() - 6);
  Mesh mixed = cube(false);
  std::swap(mixed.indices[1], mixed.indices[2]);
  std::swap(mixed.indices[4], mixed.indices[5]);
  for (const bool split : {false, true}) {
    EXPECT_EQ(meshFacing(cube(split)), MeshFacing::closedOutward);
    EXPECT_EQ(meshFacing(flip(cube(split))), MeshFacing::closedInward);
  }
  EXPECT_EQ(meshFacing(flip(cube(true, glm::vec3(3.0e6f, -2.0e6f, 1.0e6f)))), MeshFacing::closedInward);
  for (const Mesh& mesh : {open, flip(open), mixed, flip(mixed), Mesh{}}) EXPECT_EQ(meshFacing(mesh), MeshFacing::open);
  Mesh nan = flip(cube(false));
  nan.positions[3].y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(meshFacing(nan), MeshFacing::open);
}

// A scene's facings, one per mesh in order; a mesh not loaded (no arrays) is drawn from both sides.
TEST(MeshClosure, ASceneGivesEachMeshItsFacing) {
  Scene scene;
  Mesh inward = cube(true);
  for (std::size_t t = 0; t < inward.indices.size(); t += 3) std::swap(inward.indices[t + 1], inward.indices[t + 2]);
  Mesh unloaded = cube(false);
  unloaded.positions.clear();
  unloaded.indices.clear();
  scene.meshes = {cube(false), inward, unloaded};
  EXPECT_EQ(meshFacings(scene),
            (std::vector<MeshFacing>{MeshFacing::closedOutward, MeshFacing::closedInward, MeshFacing::open}));
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
}

}  // namespace
}  // namespace pbs
