// SurfelCache and the reads it makes: the same frames, bit for bit, as with the whole file read, from
// only the chunks the frames draw; a budget that drops the arrays drawn longest ago; readRange.
#include "cli_scenes.hpp"
#include "surfeled_scene.hpp"
#include "test_fixtures.hpp"
#include "test_support.hpp"

#include <pbs/scene/input_error.hpp>
#include <pbs/scene/scene_fingerprint.hpp>
#include <pbs/surfels/camera_paths.hpp>
#include <pbs/surfels/frame_renderer.hpp>
#include <pbs/surfels/surfel_cache.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstring>
#include <filesystem>

namespace pbs {
namespace {

using test::ScratchDir;

// With a budget of one byte every array not drawn by the current frame is dropped after it, so later
// frames read again what earlier ones dropped: the images must not notice.
TEST(SurfelCache, FramesAreTheWholeFilesBitForBitWhateverTheBudget) {
  ScratchDir scratch;
  const test::SurfeledScene s = test::writtenSurfeledScene(scratch / "g.surfels");
  const SceneSurfels whole = loadSceneSurfels(scratch / "g.surfels", s.scene, s.hierarchy);
  LodOptions lod;
  lod.descendExhausted = false;  // the groups as surfels even where they fill much of the view
  const FrameOptions options{.mode = RenderMode::Surfels, .lod = lod};
  FrameRenderer reference(s.scene, s.hierarchy, options, 160, 120, {.surfels = &whole});
  for (const std::uint64_t budget : {std::uint64_t(1), std::uint64_t(1) << 30}) {
    SurfelCache cache(scratch / "g.surfels", s.scene, s.hierarchy, budget);
    FrameRenderer streamed(s.scene, s.hierarchy, options, 160, 120, {.cache = &cache});
    std::uint64_t surfelsDrawn = 0;
    for (const Camera& camera : test::approachCameras(s, 6)) {
      const FrameResult a = reference.render(camera), b = streamed.render(camera);
      EXPECT_TRUE(test::sameBits(a.image, b.image)) << "budget " << budget;
      surfelsDrawn += b.stats.surfels;
      if (budget == 1) {
        std::uint64_t loaded = 0;
        for (const SplatArray& array : cache.surfels().arrays) loaded += array.loaded();
        EXPECT_EQ(loaded * kSplatBytesPerSurfel, cache.stats().bytesLoaded);
        EXPECT_LE(cache.stats().bytesLoaded,
                  (b.stats.surfels + 2 * b.stats.nodesSurfels * kSurfelsPerChunk) * kSplatBytesPerSurfel)
            << "only what this frame draws, in whole chunks and one chunk ahead";
      }
    }
    ASSERT_GT(surfelsDrawn, 0u);
    if (budget == 1)
      EXPECT_GT(cache.stats().arraysDropped, 0u);
    else
      EXPECT_EQ(cache.stats().arraysDropped, 0u);
  }
}

// A far view draws short prefixes: the cache reads their chunks, not the file.
TEST(SurfelCache, AFarViewReadsOnlyItsPrefixesChunks) {
  ScratchDir scratch;
  const test::SurfeledScene s = test::writtenSurfeledScene(scratch / "g.surfels");
  SurfelCache cache(scratch / "g.surfels", s.scene, s.hierarchy, std::uint64_t(1) << 30);
  for (const SplatArray& array : cache.surfels().arrays) EXPECT_EQ(array.loaded(), 0u) << "tables only at first";
  FrameRenderer renderer(s.scene, s.hierarchy, {.mode = RenderMode::Surfels}, 160, 120, {.cache = &cache});
  const FrameResult far = renderer.render(test::approachCameras(s, 2, 40.0).front());
  ASSERT_GT(far.stats.surfels, 0u);
  std::uint64_t fileSurfels = 0;
  for (const SplatArray& array : cache.surfels().arrays) fileSurfels += array.size();
  const std::uint64_t chunksDrawn = (far.stats.surfels + kSurfelsPerChunk - 1) / kSurfelsPerChunk;
  EXPECT_LE(cache.stats().bytesRead, (chunksDrawn + far.stats.nodesSurfels) * (kSurfelsPerChunk * kSurfelBytes + 8));
  EXPECT_LT(cache.stats().bytesRead, fileSurfels * kSurfelBytes / 2) << "well under the file's data";
}

TEST(SurfelCache, AnotherScenesFileIsRefused) {
  ScratchDir scratch;
  test::writtenSurfeledScene(scratch / "g.surfels");
  Scene other = test::twoIdenticalGroups();
  other.meshes[0].positions[0].x += 0.5f;
  const Hierarchy hierarchy = analyzeHierarchy(other);
  ASSERT_NE(sceneFingerprint(other), sceneFingerprint(test::twoIdenticalGroups()));
  EXPECT_THROW(SurfelCache(scratch / "g.surfels", other, hierarchy, 1 << 20), InputError);
}

// The file's instance boxes stand in for the scene's vertices: the hierarchy made from them is
// analyzeHierarchy's, bit for bit, here with one group turned about an oblique axis (where a box of the
// turned corners would be loose) and far from the origin.
TEST(SurfelCache, TheFilesInstanceBoxesGiveTheScenesHierarchyBitForBit) {
  ScratchDir scratch;
  Scene scene = test::twoIdenticalGroups();
  scene.nodes[scene.roots.front()].local =
      glm::translate(glm::dmat4(1.0), glm::dvec3(3e5, -2e4, 7.25)) *
      glm::rotate(glm::dmat4(1.0), 0.52, glm::normalize(glm::dvec3(1.0, 2.0, -0.5)));
  const Hierarchy computed = analyzeHierarchy(scene);
  SurfelizeOptions options;
  options.file.threshold = 1000;
  options.file.maxSurfels = 100;
  options.file.resolution = 32;
  surfelizeToFile(scene, computed, options, scratch / "r.surfels");

  SurfelFileReader reader(scratch / "r.surfels");
  ASSERT_EQ(reader.sceneTable().instanceBounds.size(), scene.nodes.size());
  const Hierarchy stored = hierarchyWithSurfels(scene, reader);
  EXPECT_TRUE(reader.sceneRequired());
  ASSERT_EQ(stored.preorder, computed.preorder);
  EXPECT_EQ(stored.parent, computed.parent);
  EXPECT_EQ(stored.depth, computed.depth);
  EXPECT_EQ(stored.subtreeTriangles, computed.subtreeTriangles);
  for (std::size_t n = 0; n < scene.nodes.size(); ++n) {
    EXPECT_EQ(stored.world[n], computed.world[n]) << n;
    EXPECT_EQ(stored.instanceBounds[n].min, computed.instanceBounds[n].min) << n;
    EXPECT_EQ(stored.instanceBounds[n].max, computed.instanceBounds[n].max) << n;
    EXPECT_EQ(stored.worldBounds[n].min, computed.worldBounds[n].min) << n;
    EXPECT_EQ(stored.worldBounds[n].max, computed.worldBounds[n].max) << n;
  }
  // The turned group's boxes are the exact ones, tighter than its turned corners.
  const std::uint32_t mesh =
      std::uint32_t(std::find_if(scene.nodes.begin(), scene.nodes.end(), [](const Node& n) { return n.mesh >= 0; }) -
                    scene.nodes.begin());
  const Bounds corners =
      transformCorners(scene.meshes[std::size_t(scene.nodes[mesh].mesh)].bounds, computed.world[mesh]);
  EXPECT_LT(glm::length(stored.instanceBounds[mesh].size()), glm::length(corners.size()));

  // A reader not required for the scene cannot feed a cache.
  EXPECT_THROW(SurfelCache(SurfelFileReader(scratch / "r.surfels"), scene, stored, 1 << 20), std::logic_error);
  // Given boxes must match the scene's nodes.
  EXPECT_THROW(analyzeHierarchy(scene, std::span(reader.sceneTable().instanceBounds).first(1)), std::invalid_argument);
}

TEST(SurfelFileReader, RangesAreSlicesOfThePrefix) {
  ScratchDir scratch;
  test::writtenSurfeledScene(scratch / "g.surfels");
  SurfelFileReader reader(scratch / "g.surfels");
  ASSERT_FALSE(reader.arrays().empty());
  const std::uint32_t count = reader.arrays()[0].count;
  ASSERT_GT(count, 2 * kSurfelsPerChunk);
  const std::vector<Surfel> whole = reader.readPrefix(0, count);
  const std::uint64_t before = reader.dataBytesRead();
  const std::vector<Surfel> second = reader.readRange(0, kSurfelsPerChunk, kSurfelsPerChunk);
  EXPECT_EQ(reader.dataBytesRead() - before, storedSurfelBytes(kSurfelsPerChunk, reader.arrays()[0].colorEncoding))
      << "one chunk and its checksum";
  ASSERT_EQ(second.size(), kSurfelsPerChunk);
  for (std::size_t i = 0; i < second.size(); ++i) {
    EXPECT_EQ(second[i].position, whole[kSurfelsPerChunk + i].position);
    EXPECT_EQ(second[i].color, whole[kSurfelsPerChunk + i].color);
  }
  EXPECT_EQ(reader.readRange(0, 2 * kSurfelsPerChunk, count).size(), count - 2 * kSurfelsPerChunk) << "clamped";
  EXPECT_TRUE(reader.readRange(0, count + kSurfelsPerChunk - count % kSurfelsPerChunk, 10).empty());
  EXPECT_THROW(reader.readRange(0, 5, 10), std::invalid_argument);
}

// The command reads on demand: a tiny cache draws the same frames as a large one.
TEST(SurfelCacheCli, RenderWithATinyCacheDrawsTheSameFrames) {
  ScratchDir scratch;
  const auto [scene, surfels] = test::groupsWithSurfels(scratch);
  const std::string common =
      "render " + scene + " --surfels " + surfels +
      " --size 160x120 --path approach --frames 4 --exhausted grow --rays-cheaper keep --json -o ";
  const test::CommandResult tiny = test::runPbs(common + "'" + (scratch / "tiny").string() + "' --cache-mb 1");
  const test::CommandResult large = test::runPbs(common + "'" + (scratch / "large").string() + "'");
  ASSERT_EQ(tiny.status, 0) << tiny.err;
  ASSERT_EQ(large.status, 0) << large.err;
  for (int f = 0; f < 4; ++f) {
    const std::string name = "frame_000" + std::to_string(f) + ".png";
    EXPECT_EQ(test::readFile(scratch / "tiny" / name), test::readFile(scratch / "large" / name)) << name;
  }
  const nlohmann::json report = nlohmann::json::parse(tiny.out);
  EXPECT_GT(report["surfel_bytes_read"].get<std::uint64_t>(), 0u);
  EXPECT_LE(report["surfel_bytes_read"].get<std::uint64_t>(), std::filesystem::file_size(scratch / "groups.surfels"));
  EXPECT_EQ(test::runPbs(common + "x --cache-mb 0").status, 2);
}

}  // namespace
}  // namespace pbs
