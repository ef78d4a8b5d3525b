// surfelize of a glTF scene opened without its mesh arrays (each capture decodes what it draws): the file
// of the scene read whole, byte for byte, for every capture source, thread count and cache budget; a mesh
// that changes while the run reads it is refused by name; `pbs surfelize` takes this road for a glTF file.
#include "test_fixtures.hpp"
#include "test_support.hpp"

#include <pbs/scene/gltf_export.hpp>
#include <pbs/scene/gltf_import.hpp>
#include <pbs/scene/input_error.hpp>
#include <pbs/surfels/surfelize.hpp>

#include <nlohmann/json.hpp>
#include <tbb/task_arena.h>

#include <atomic>
#include <mutex>

namespace pbs {
namespace {

using test::ScratchDir;

// Small enough to run in a moment, large enough that leaves, groups and the root get arrays and that
// `auto` captures some of them from their children's surfels.
SurfelizeOptions smallArrays(CaptureSource source) {
  SurfelizeOptions options;
  options.file.threshold = 1000;
  options.file.maxSurfels = 300;
  options.file.resolution = 48;
  options.source = source;
  return options;
}

std::uint64_t bytesOfAllMeshes(const Scene& scene) {
  std::uint64_t bytes = 0;
  for (const Mesh& mesh : scene.meshes) bytes += meshBytes(mesh);
  return bytes;
}

TEST(LazySurfelize, FileIsTheLoadedScenesByteForByte) {
  ScratchDir scratch;
  writeGlb(test::layeredScene(), scratch / "layered.glb");
  const ImportResult whole = importGltf(scratch / "layered.glb");
  const Hierarchy hierarchy = analyzeHierarchy(whole.scene);
  for (const CaptureSource source : {CaptureSource::Auto, CaptureSource::Triangles, CaptureSource::ChildSurfels}) {
    const SurfelizeOptions options = smallArrays(source);
    SurfelizeStats eagerStats;
    surfelizeToFile(whole.scene, hierarchy, options, scratch / "eager.surfels", &eagerStats);
    ASSERT_GE(eagerStats.arrays, 5u) << "leaves, groups and root";
    const std::string eager = test::readFile(scratch / "eager.surfels");
    for (const int threads : {1, 2, 4}) {
      for (const std::uint64_t budget : {std::uint64_t(1), std::uint64_t(1) << 30}) {
        SCOPED_TRACE(std::string(captureSourceName(source)) + ", " + std::to_string(threads) + " threads, budget " +
                     std::to_string(budget));
        LazyGltf lazy = openGltfWithoutMeshes(scratch / "layered.glb");
        SurfelizeStats stats;
        tbb::task_arena(threads).execute([&] {
          surfelizeToFile(lazy.imported.scene, lazy.decode, budget, "layered.glb", options, scratch / "lazy.surfels",
                          &stats);
        });
        EXPECT_EQ(test::readFile(scratch / "lazy.surfels"), eager);
        EXPECT_EQ(stats.arrays, eagerStats.arrays);
        EXPECT_GT(stats.meshesDecoded, 0u);
        if (threads == 1 && budget == 1 && source == CaptureSource::ChildSurfels) {
          EXPECT_LT(stats.meshPeakBytesLoaded, bytesOfAllMeshes(whole.scene))
              << "captured from the children, no capture needs every mesh at once, nor the cache keeps them";
        }
      }
    }
  }
}

// The scan and the captures read each mesh separately: a mesh whose bytes change in between is refused,
// naming the mesh, and no file is left.
TEST(LazySurfelize, AMeshThatChangesWhileReadIsRefused) {
  ScratchDir scratch;
  writeGlb(test::layeredScene(), scratch / "layered.glb");
  LazyGltf lazy = openGltfWithoutMeshes(scratch / "layered.glb");
  std::mutex mutex;
  std::vector<int> reads(lazy.imported.scene.meshes.size(), 0);
  const auto changing = [&](std::uint32_t m) {
    Mesh mesh = lazy.decode(m);
    const std::lock_guard lock(mutex);
    if (++reads[m] > 1) mesh.positions[0].x += 0.25f;  // after the scan
    return mesh;
  };
  try {
    surfelizeToFile(lazy.imported.scene, changing, 1, "layered.glb", smallArrays(CaptureSource::Triangles),
                    scratch / "f.surfels");
    ADD_FAILURE() << "a mesh that changed was captured";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("layered.glb: mesh "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("differs from the mesh the surfels were made from"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(scratch / "f.surfels"));
}

// From the command line: a glTF file is surfelized with its meshes read as the captures draw them, into
// the file the library makes from the loaded scene; the embedded scene is made whole.
TEST(LazySurfelizeCli, SurfelizeReadsAGltfsMeshesAsCapturesDrawThem) {
  ScratchDir scratch;
  writeGlb(test::layeredScene(), scratch / "layered.glb");
  const ImportResult whole = importGltf(scratch / "layered.glb");
  SurfelizeOptions options = smallArrays(CaptureSource::Auto);
  surfelizeToFile(whole.scene, analyzeHierarchy(whole.scene), options, scratch / "library.surfels");

  const test::CommandResult made =
      test::runPbs("surfelize '" + (scratch / "layered.glb").string() + "' -o '" + (scratch / "cli.surfels").string() +
                   "' --min-triangles 1000 --max-surfels 300 --resolution 48 --json");
  ASSERT_EQ(made.status, 0) << made.err;
  const nlohmann::json report = nlohmann::json::parse(made.out);
  EXPECT_EQ(report["used"]["meshes"], "read as captures draw them");
  EXPECT_GT(report["meshes_decoded"].get<int>(), 0);
  EXPECT_EQ(test::readFile(scratch / "cli.surfels"), test::readFile(scratch / "library.surfels"));
}

}  // namespace
}  // namespace pbs
