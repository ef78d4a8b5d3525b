// A glTF scene opened without its mesh arrays (openGltfWithoutMeshes) and read as frames draw it
// (LazyMeshes): the same scene once decoded, the same frames bit for bit whatever the budget, a mesh that
// changed since the surfels were made refused by name, and `pbs render` doing it from the command line.
#include "cli_scenes.hpp"
#include "gltf_test_files.hpp"
#include "surfeled_scene.hpp"
#include "test_fixtures.hpp"
#include "test_support.hpp"

#include <pbs/scene/gltf_export.hpp>
#include <pbs/scene/gltf_import.hpp>
#include <pbs/scene/input_error.hpp>
#include <pbs/scene/lazy_meshes.hpp>
#include <pbs/scene/load_scene.hpp>
#include <pbs/scene/scene_fingerprint.hpp>
#include <pbs/surfels/frame_renderer.hpp>
#include <pbs/surfels/surfel_cache.hpp>

#include <nlohmann/json.hpp>

#include <tbb/parallel_for.h>

#include <atomic>
#include <numeric>

namespace pbs {
namespace {

using test::ScratchDir;

std::vector<std::uint64_t> meshFingerprints(const Scene& scene) {
  std::vector<std::uint64_t> fingerprints;
  for (const Mesh& mesh : scene.meshes) fingerprints.push_back(meshFingerprint(mesh));
  return fingerprints;
}

std::vector<std::uint32_t> allMeshes(const Scene& scene) {
  std::vector<std::uint32_t> meshes(scene.meshes.size());
  std::iota(meshes.begin(), meshes.end(), 0u);
  return meshes;
}

// Meshes the importer must take apart the same way opened lazily as whole: two primitives sharing one
// vertex accessor with two materials (the second textured), a non-indexed strip and an indexed fan
// without normals beside a skipped POINTS primitive, a mesh of LINES alone (no triangles: its node gets
// no mesh), and materials first used in an order that is not their index order.
test::GltfBuilder variedPrimitives() {
  test::GltfBuilder b;
  const int quad = b.addAccessor(std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, test::kFloat, "VEC3");
  const int normals = b.addAccessor(std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, test::kFloat, "VEC3");
  const int uvs = b.addAccessor(std::vector<float>{0, 0, 1, 0, 1, 1, 0, 1}, test::kFloat, "VEC2");
  const int first = b.addAccessor(std::vector<std::uint16_t>{0, 1, 2}, test::kUnsignedShort, "SCALAR");
  const int second = b.addAccessor(std::vector<std::uint16_t>{0, 2, 3}, test::kUnsignedShort, "SCALAR");
  const int strip =
      b.addAccessor(std::vector<float>{0, 0, 1, 1, 0, 1, 0, 1, 2, 1, 1, 2, 0, 2, 1}, test::kFloat, "VEC3");
  const int fan = b.addAccessor(std::vector<std::uint8_t>{0, 1, 2, 3}, test::kUnsignedByte, "SCALAR");
  b.addMaterial({{"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.4, 0.6, 1.0}}}}});
  b.addMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  b.addMaterial({{"pbrMetallicRoughness", {{"baseColorFactor", {0.9, 0.1, 0.1, 1.0}}}}});
  b.append("textures", {{"source", 0}});
  b.append("images", {{"uri", std::string("data:image/png;base64,") + test::kPngRgba2x2}});
  b.addMesh({{{"attributes", {{"POSITION", quad}, {"NORMAL", normals}, {"TEXCOORD_0", uvs}}},
              {"indices", first},
              {"material", 2}},
             {{"attributes", {{"POSITION", quad}, {"NORMAL", normals}, {"TEXCOORD_0", uvs}}},
              {"indices", second},
              {"material", 1}}});
  b.addMesh({{{"attributes", {{"POSITION", strip}}}, {"mode", 5}},
             {{"attributes", {{"POSITION", strip}}}, {"mode", 0}},
             {{"attributes", {{"POSITION", quad}}}, {"indices", fan}, {"mode", 6}}});
  b.addMesh({{{"attributes", {{"POSITION", quad}}}, {"mode", 1}}});
  b.addNode({{"mesh", 1}, {"translation", {3.0, 0.0, 0.0}}});
  b.addNode({{"mesh", 0}, {"rotation", {0.0, 0.3826834, 0.0, 0.9238795}}});
  b.addNode({{"mesh", 2}});
  b.addNode({{"mesh", 1}, {"scale", {2.0, 1.0, 0.5}}});
  b.addNode({{"children", {0, 1, 2, 3}}});
  b.setScene({4});
  return b;
}

// Opened without meshes, then every mesh decoded through LazyMeshes: the imported scene, fingerprint for
// fingerprint, with the same warnings; before decoding, the same structure.
void expectSameSceneOnceDecoded(const std::filesystem::path& file) {
  SCOPED_TRACE(file.string());
  const ImportResult whole = importGltf(file);
  LazyGltf lazy = loadSceneWithoutMeshes(file.string());
  Scene& scene = lazy.imported.scene;
  EXPECT_EQ(lazy.imported.warnings, whole.warnings);
  ASSERT_EQ(scene.meshes.size(), whole.scene.meshes.size());
  for (const Mesh& mesh : scene.meshes) EXPECT_FALSE(mesh.loaded());
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    EXPECT_EQ(scene.meshes[m].triangleCount(), whole.scene.meshes[m].triangleCount()) << "mesh " << m;
    EXPECT_EQ(scene.meshes[m].vertexCount(), whole.scene.meshes[m].positions.size()) << "mesh " << m;
  }
  EXPECT_EQ(structureFingerprint(scene), structureFingerprint(whole.scene));

  LazyMeshes meshes(scene, lazy.decode, meshFingerprints(whole.scene), file.string(), std::uint64_t(1) << 30);
  const LazyMeshes::Lease all = meshes.require(allMeshes(scene));
  EXPECT_EQ(meshes.stats().decoded, scene.meshes.size());
  EXPECT_EQ(sceneFingerprint(scene), sceneFingerprint(whole.scene));
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    EXPECT_EQ(scene.meshes[m].bounds.min, whole.scene.meshes[m].bounds.min) << "mesh " << m;
    EXPECT_EQ(scene.meshes[m].bounds.max, whole.scene.meshes[m].bounds.max) << "mesh " << m;
  }
}

TEST(LazyMeshes, OpenedWithoutMeshesThenDecodedIsTheImportedScene) {
  ScratchDir scratch;
  test::writeFile(scratch / "varied.glb", variedPrimitives().glb());
  test::writeFile(scratch / "varied.gltf", variedPrimitives().gltf());
  writeGlb(test::twoIdenticalGroups(), scratch / "groups.glb");
  for (const char* name : {"varied.glb", "varied.gltf", "groups.glb"}) expectSameSceneOnceDecoded(scratch / name);

  const LazyGltf varied = openGltfWithoutMeshes(scratch / "varied.glb");
  EXPECT_EQ(varied.imported.scene.meshes.size(), 2u) << "the mesh of LINES alone is not a mesh";
  EXPECT_EQ(varied.imported.scene.meshes[1].parts.size(), 2u) << "strip and fan; the points are skipped";
}

// The real meshes, where the shared scenes are at hand.
TEST(LazyMeshes, SharedScenesOpenedWithoutMeshesAreTheImportedOnes) {
  const auto dir = test::sharedScenesDir();
  if (!dir) GTEST_SKIP() << "no shared scenes (PBS_SCENES)";
  for (const char* name : {"bunny.glb", "spot.glb"})
    if (std::filesystem::exists(*dir / name)) expectSameSceneOnceDecoded(*dir / name);
}

TEST(LazyMeshes, UnloadsTheLeastRecentlyDrawnAndRefusesAChangedMesh) {
  ScratchDir scratch;
  test::writeFile(scratch / "varied.glb", variedPrimitives().glb());
  const ImportResult whole = importGltf(scratch / "varied.glb");
  LazyGltf lazy = openGltfWithoutMeshes(scratch / "varied.glb");
  Scene& scene = lazy.imported.scene;
  LazyMeshes meshes(scene, lazy.decode, meshFingerprints(whole.scene), "varied.glb", 1);
  const std::uint32_t first[] = {0}, second[] = {1};
  // Other threads read a mesh's parts leased or not (a subtree's triangle count): loading and unloading
  // must leave them where they are.
  const MeshPart* const parts = scene.meshes[0].parts.data();
  {
    const LazyMeshes::Lease drawing = meshes.require(first);
    EXPECT_TRUE(meshes.unloadOverBudget().empty()) << "never a leased mesh";
  }
  LazyMeshes::Lease drawing = meshes.require(second);
  EXPECT_EQ(meshes.unloadOverBudget(), std::vector<std::uint32_t>{0});
  EXPECT_FALSE(scene.meshes[0].loaded());
  EXPECT_EQ(scene.meshes[0].triangleCount(), whole.scene.meshes[0].triangleCount()) << "the parts stay";
  EXPECT_EQ(scene.meshes[0].vertexCount(), whole.scene.meshes[0].positions.size()) << "and the vertex count";
  EXPECT_TRUE(scene.meshes[1].loaded());
  drawing = meshes.require(first);
  EXPECT_EQ(scene.meshes[0].parts.data(), parts) << "loaded, unloaded and loaded again: the same parts";
  EXPECT_EQ(meshes.stats().decoded, 3u);
  EXPECT_EQ(meshes.stats().unloaded, 1u);
  EXPECT_EQ(meshFingerprint(scene.meshes[0]), meshFingerprint(whole.scene.meshes[0]));

  LazyGltf again = openGltfWithoutMeshes(scratch / "varied.glb");
  std::vector<std::uint64_t> wrong = meshFingerprints(whole.scene);
  wrong[1] ^= 1;
  LazyMeshes changed(again.imported.scene, again.decode, wrong, "varied.glb", 1 << 20);
  try {
    (void)changed.require(second);
    ADD_FAILURE() << "a mesh unlike the one the surfels were made from was drawn";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("varied.glb: mesh 1: differs from the mesh the surfels were made from"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(LazyMeshes(again.imported.scene, again.decode, {1}, "varied.glb", 1), std::invalid_argument);
}

// The frames of a scene whose meshes are read as they are drawn are those of the scene read whole, bit for
// bit, with a budget so small that every mesh a frame does not draw is unloaded (and its ray BVH let go).
TEST(LazyMeshes, FramesAreTheWholeScenesBitForBitWhateverTheBudget) {
  ScratchDir scratch;
  writeGlb(test::groupsOfFourMeshes(), scratch / "four.glb");
  const ImportResult whole = importGltf(scratch / "four.glb");
  const Hierarchy hierarchy = analyzeHierarchy(whole.scene);
  SurfelizeOptions options;
  options.file.threshold = 1000;
  options.file.maxSurfels = 2000;
  options.file.resolution = 64;
  surfelizeToFile(whole.scene, hierarchy, options, scratch / "four.surfels");
  const test::SurfeledScene path{whole.scene, hierarchy, {}};

  for (const GeometryDrawer drawer : {GeometryDrawer::Raster, GeometryDrawer::Rays}) {
    for (const std::uint64_t budget : {std::uint64_t(1), std::uint64_t(1) << 30}) {
      SCOPED_TRACE(std::string(geometryDrawerName(drawer)) + ", budget " + std::to_string(budget));
      LodOptions lod;
      lod.geometry = drawer;
      const FrameOptions frame{.mode = RenderMode::Surfels, .lod = lod};
      SurfelCache wholeCache(scratch / "four.surfels", whole.scene, hierarchy, 1 << 30);
      FrameRenderer reference(whole.scene, hierarchy, frame, 160, 120, {.cache = &wholeCache});

      SurfelFileReader reader(scratch / "four.surfels");
      LazyGltf lazy = openGltfWithoutMeshes(scratch / "four.glb");
      reader.requireStructure(structureFingerprint(lazy.imported.scene));
      const Hierarchy lazyHierarchy = analyzeHierarchy(lazy.imported.scene, reader.sceneTable().instanceBounds);
      LazyMeshes meshes(lazy.imported.scene, lazy.decode, reader.sceneTable().meshes, "four.glb", budget);
      SurfelCache cache(std::move(reader), lazy.imported.scene, lazyHierarchy, 1 << 30);
      FrameRenderer onDemand(lazy.imported.scene, lazyHierarchy, frame, 160, 120, {.cache = &cache, .meshes = &meshes});

      std::uint64_t geometryNodes = 0;
      for (const Camera& camera : test::approachCameras(path, 6, 3.0)) {
        const FrameResult a = reference.render(camera), b = onDemand.render(camera);
        EXPECT_TRUE(test::sameBits(a.image, b.image));
        geometryNodes += b.stats.nodesGeometry;
      }
      EXPECT_GT(geometryNodes, 0u) << "the near frames draw geometry";
      if (budget == 1) {
        EXPECT_GT(meshes.stats().unloaded, 0u);
        EXPECT_LT(meshes.stats().loaded, lazy.imported.scene.meshes.size()) << "only the last frame's meshes stay";
      } else {
        EXPECT_EQ(meshes.stats().unloaded, 0u);
        EXPECT_EQ(meshes.stats().decoded, meshes.stats().loaded) << "each mesh decoded once";
      }
    }
  }
}

// Exact frames of a scene read on demand are drawn node by node, a budget's worth of meshes at a time:
// the frames drawing every node at once, bit for bit, at one sample and supersampled.
TEST(LazyMeshes, ExactFramesDrawnNodeByNodeAreTheWholeScenes) {
  ScratchDir scratch;
  writeGlb(test::layeredScene(), scratch / "layered.glb");
  const ImportResult whole = importGltf(scratch / "layered.glb");
  const Hierarchy hierarchy = analyzeHierarchy(whole.scene);
  const test::SurfeledScene path{whole.scene, hierarchy, {}};
  for (const std::uint32_t samples : {1u, 4u}) {
    for (const std::uint64_t budget : {std::uint64_t(1), std::uint64_t(1) << 30}) {
      SCOPED_TRACE(std::to_string(samples) + " samples, budget " + std::to_string(budget));
      const FrameOptions exact{.mode = RenderMode::Exact, .lod = {}, .samples = samples};
      FrameRenderer reference(whole.scene, hierarchy, exact, 160, 120, {});
      LazyGltf lazy = openGltfWithoutMeshes(scratch / "layered.glb");
      const Hierarchy lazyHierarchy = analyzeHierarchy(lazy.imported.scene, hierarchy.instanceBounds);
      LazyMeshes meshes(lazy.imported.scene, lazy.decode, meshFingerprints(whole.scene), "layered.glb", budget);
      FrameRenderer byNodes(lazy.imported.scene, lazyHierarchy, exact, 160, 120, {.meshes = &meshes});
      for (const Camera& camera : test::approachCameras(path, 4, 3.0)) {
        const FrameResult a = reference.render(camera), b = byNodes.render(camera);
        EXPECT_TRUE(test::sameBits(a.image, b.image));
        EXPECT_EQ(a.stats.triangles, b.stats.triangles);
      }
      if (budget == 1) {
        EXPECT_GT(meshes.stats().unloaded, 0u) << "batches of one mesh, each let go after";
        EXPECT_LE(meshes.stats().peakBytesLoaded, 2 * meshBytes(whole.scene.meshes[2])) << "the largest mesh, about";
      }
    }
  }
}

// Captures run side by side and require overlapping meshes: each mesh is decoded once (a call that finds
// it being decoded waits for it), is whole while leased, and a decoder's failure reaches every caller that
// needed the mesh and leaves no lease behind.
TEST(LazyMeshes, ConcurrentRequiresDecodeEachMeshOnceAndShareFailures) {
  ScratchDir scratch;
  writeGlb(test::groupsOfFourMeshes(), scratch / "four.glb");
  const ImportResult whole = importGltf(scratch / "four.glb");
  LazyGltf lazy = openGltfWithoutMeshes(scratch / "four.glb");
  const std::size_t meshCount = lazy.imported.scene.meshes.size();
  ASSERT_EQ(meshCount, 4u);
  std::vector<std::atomic<int>> decodes(meshCount);
  const auto counted = [&](std::uint32_t m) {
    ++decodes[m];
    return lazy.decode(m);
  };
  LazyMeshes meshes(lazy.imported.scene, counted, meshFingerprints(whole.scene), "four.glb", std::uint64_t(1) << 30);
  std::atomic<int> wrong{0};
  tbb::parallel_for(0, 64, [&](int i) {
    const std::uint32_t wanted[] = {std::uint32_t(i % 4), std::uint32_t((i + 1) % 4)};
    const LazyMeshes::Lease lease = meshes.require(wanted);
    for (std::uint32_t m : wanted)
      if (meshFingerprint(lazy.imported.scene.meshes[m]) != meshFingerprint(whole.scene.meshes[m])) ++wrong;
  });
  EXPECT_EQ(wrong.load(), 0);
  for (std::size_t m = 0; m < meshCount; ++m) EXPECT_EQ(decodes[m].load(), 1) << "mesh " << m;

  // With no budget every mesh is unloaded as soon as its lease ends, while other tasks count the
  // triangles of meshes they do not lease (as surfelize's workers analyse subtrees): the counts hold
  // throughout (and the sanitizer build sees no read of freed parts).
  LazyGltf churned = openGltfWithoutMeshes(scratch / "four.glb");
  LazyMeshes churning(churned.imported.scene, churned.decode, meshFingerprints(whole.scene), "four.glb", 0);
  std::uint64_t triangles = 0;
  for (const Mesh& mesh : whole.scene.meshes) triangles += mesh.triangleCount();
  std::atomic<int> miscounted{0};
  tbb::parallel_for(0, 64, [&](int i) {
    if (i % 2 == 0) {
      const std::uint32_t wanted[] = {std::uint32_t(i / 2 % 4)};
      { const LazyMeshes::Lease lease = churning.require(wanted); }
      churning.unloadOverBudget();
      return;
    }
    std::uint64_t counted = 0;
    for (const Mesh& mesh : churned.imported.scene.meshes) counted += mesh.triangleCount();
    if (counted != triangles) ++miscounted;
  });
  EXPECT_EQ(miscounted.load(), 0);

  LazyGltf again = openGltfWithoutMeshes(scratch / "four.glb");
  const auto failing = [&](std::uint32_t m) -> Mesh {
    if (m == 2) throw InputError("four.glb", "mesh 2", "cannot be read");
    return again.decode(m);
  };
  LazyMeshes broken(again.imported.scene, failing, meshFingerprints(whole.scene), "four.glb", 0);
  std::atomic<int> failures{0};
  tbb::parallel_for(0, 16, [&](int i) {
    const std::uint32_t wanted[] = {std::uint32_t(i % 2 == 0 ? 2 : 1), 2};
    try {
      const LazyMeshes::Lease lease = broken.require(wanted);
    } catch (const InputError&) {
      ++failures;
    }
  });
  EXPECT_EQ(failures.load(), 16) << "every caller that needed mesh 2 hears of it";
  EXPECT_FALSE(again.imported.scene.meshes[2].loaded());
  broken.unloadOverBudget();
  EXPECT_EQ(broken.stats().loaded, 0u) << "no lease was left behind";
}

// From the command line: a glTF scene with a version 4 .surfels file is read as frames draw it, and a
// scene whose mesh data changed (same structure) is refused by the mesh, in one error line.
TEST(LazyMeshesCli, RenderReadsMeshesAsFramesDrawThemAndRefusesAChangedOne) {
  ScratchDir scratch;
  const auto [scene, surfels] = test::groupsWithSurfels(scratch);
  const test::CommandResult near =
      test::runPbs("render " + scene + " --surfels " + surfels + " --size 160x120 --orbit 30,20,0.6 --json");
  ASSERT_EQ(near.status, 0) << near.err;
  const nlohmann::json report = nlohmann::json::parse(near.out);
  EXPECT_EQ(report["used"]["meshes"], "read as frames draw them");
  ASSERT_GT(report["nodes_geometry"].get<int>(), 0) << "the view must draw geometry for this test";
  EXPECT_EQ(report["meshes_decoded"], 1) << "the one mesh, once";
  EXPECT_GT(report["mesh_peak_bytes_loaded"].get<double>(), 0.0);

  // One vertex moved: the same JSON, so the same structure, but mesh 0's data differs.
  std::string glb = test::readFile(scratch / "groups.glb");
  const std::uint32_t jsonLength = std::uint32_t(std::uint8_t(glb[12])) | std::uint32_t(std::uint8_t(glb[13])) << 8 |
                                   std::uint32_t(std::uint8_t(glb[14])) << 16 |
                                   std::uint32_t(std::uint8_t(glb[15])) << 24;
  glb[20 + jsonLength + 8 + 1] ^= 0x01;  // a low mantissa byte of the first position
  test::writeFile(scratch / "groups.glb", glb);
  const test::CommandResult changed =
      test::runPbs("render " + scene + " --surfels " + surfels + " --size 160x120 --orbit 30,20,0.6 -o " +
                   (scratch / "x.png").string());
  EXPECT_NE(changed.status, 0);
  EXPECT_NE(changed.err.find("mesh 0: differs from the mesh the surfels were made from"), std::string::npos)
      << changed.err;
  EXPECT_FALSE(std::filesystem::exists(scratch / "x.png"));
}

}  // namespace
}  // namespace pbs
