// scanScene against the whole-scene functions it stands in for (sceneFingerprint, analyzeHierarchy's and
// analyzeSubtree's boxes, ownFrameSurfaceAreas): the same values bit for bit, from the loaded meshes or
// from copies read one at a time, on any thread count; and the streaming fingerprint's definition pinned.
#include "test_fixtures.hpp"
#include "test_support.hpp"

#include <pbs/scene/gltf_import.hpp>
#include <pbs/scene/mesh_closure.hpp>
#include <pbs/scene/scene_fingerprint.hpp>
#include <pbs/scene/scene_scan.hpp>
#include <pbs/scene/surface_area.hpp>

#include <tbb/task_arena.h>

#include <atomic>
#include <stdexcept>

namespace pbs {
namespace {

void expectSameBox(const Bounds& a, const Bounds& b, const std::string& what) {
  EXPECT_EQ(a.min, b.min) << what;
  EXPECT_EQ(a.max, b.max) << what;
}

void expectScanIsTheWholeScenes(const Scene& scene, const MeshReader& read) {
  const Hierarchy whole = analyzeHierarchy(scene);
  const std::vector<std::uint32_t>& starts = whole.preorder;  // every node a subtree start
  const SceneScan scan =
      scanScene(scene, analyzeStructure(scene),
                {.worldBounds = true, .subtreeStarts = starts, .ownFrameAreas = true, .meshClosures = true}, read);
  EXPECT_EQ(scan.sceneFingerprint, sceneFingerprint(scene));
  ASSERT_EQ(scan.meshFingerprints.size(), scene.meshes.size());
  for (std::size_t m = 0; m < scene.meshes.size(); ++m)
    EXPECT_EQ(scan.meshFingerprints[m], meshFingerprint(scene.meshes[m])) << "mesh " << m;
  ASSERT_EQ(scan.meshClosures.size(), scene.meshes.size());
  for (std::size_t m = 0; m < scene.meshes.size(); ++m)
    EXPECT_EQ(scan.meshClosures[m].facing, meshClosure(scene.meshes[m]).facing) << "mesh " << m;
  ASSERT_EQ(scan.instanceBounds.size(), scene.nodes.size());
  for (std::size_t n = 0; n < scene.nodes.size(); ++n)
    expectSameBox(scan.instanceBounds[n], whole.instanceBounds[n], "world box of node " + std::to_string(n));
  ASSERT_EQ(scan.subtreeBounds.size(), starts.size());
  for (std::size_t s = 0; s < starts.size(); ++s) {
    const Hierarchy eager = analyzeSubtree(scene, starts[s]);
    const Hierarchy given = analyzeSubtree(scene, starts[s], scan.subtreeBounds[s]);
    ASSERT_EQ(given.preorder, eager.preorder);
    for (std::uint32_t n : eager.preorder) {
      const std::string what = "node " + std::to_string(n) + " below " + std::to_string(starts[s]);
      EXPECT_EQ(given.world[n], eager.world[n]) << what;
      expectSameBox(given.instanceBounds[n], eager.instanceBounds[n], what);
      expectSameBox(given.worldBounds[n], eager.worldBounds[n], what);
      EXPECT_EQ(given.subtreeTriangles[n], eager.subtreeTriangles[n]) << what;
    }
  }
  const std::vector<double> areas = ownFrameSurfaceAreas(scene, whole);
  ASSERT_EQ(scan.ownFrameAreas.size(), areas.size());
  for (std::size_t n = 0; n < areas.size(); ++n) EXPECT_EQ(scan.ownFrameAreas[n], areas[n]) << "area of node " << n;
}

TEST(SceneScan, EqualsTheWholeSceneFunctionsBitForBit) {
  const Scene scene = test::layeredScene();
  std::atomic<int> copies{0};
  const MeshReader copying = [&](std::uint32_t m) {
    ++copies;
    return std::make_shared<const Mesh>(scene.meshes[m]);
  };
  for (const int threads : {1, 3}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    tbb::task_arena arena(threads);
    arena.execute([&] {
      expectScanIsTheWholeScenes(scene, loadedMeshes(scene));
      copies = 0;
      expectScanIsTheWholeScenes(scene, copying);
      EXPECT_EQ(copies.load(), int(scene.meshes.size())) << "each mesh read once";
    });
  }
}

TEST(SceneScan, AskedNothingItStillFingerprints) {
  const Scene scene = test::twoIdenticalGroups();
  const SceneScan scan = scanScene(scene, analyzeStructure(scene), {}, loadedMeshes(scene));
  EXPECT_EQ(scan.sceneFingerprint, sceneFingerprint(scene));
  EXPECT_TRUE(scan.instanceBounds.empty());
  EXPECT_TRUE(scan.subtreeBounds.empty());
  EXPECT_TRUE(scan.ownFrameAreas.empty());
  EXPECT_TRUE(scan.meshClosures.empty());
}

TEST(SceneScan, AnalyzeSubtreeWithBoxesRefusesAnotherCount) {
  const Scene scene = test::twoIdenticalGroups();
  const std::vector<Bounds> three(3);  // node 1's subtree holds two instances
  EXPECT_THROW(analyzeSubtree(scene, 1, three), std::invalid_argument);
  EXPECT_EQ(subtreeInstances(scene, 1).size(), 2u);
  EXPECT_EQ(subtreeInstances(scene, 0).size(), 4u);
}

TEST(SceneFingerprinter, IsSceneFingerprintAndWantsEveryMesh) {
  const Scene scene = test::groupsOfFourMeshes();
  SceneFingerprinter streamed(scene);
  for (const Mesh& mesh : scene.meshes) streamed.add(mesh);
  EXPECT_EQ(streamed.finish(), sceneFingerprint(scene));
  SceneFingerprinter short_of_one(scene);
  short_of_one.add(scene.meshes[0]);
  EXPECT_THROW(short_of_one.finish(), std::logic_error);
}

// The value for a real mesh, as computed (value by value) when .surfels files of version 4 were first
// written: a change to what the fingerprint hashes, or how, would refuse every file made before.
TEST(SceneFingerprinter, DefinitionIsPinned) {
  const auto dir = test::sharedScenesDir();
  if (!dir || !std::filesystem::exists(*dir / "bunny.glb")) GTEST_SKIP() << "no shared scenes (PBS_SCENES)";
  EXPECT_EQ(sceneFingerprint(importGltf(*dir / "bunny.glb").scene), 0x5ed303721cfd4f68ull);
}

}  // namespace
}  // namespace pbs
