// SurfelStream: nothing before the tables, never more bytes than the link carried, prefixes cut at what
// arrived (whole arrays or nothing in the baseline order), stand-ins for meshes still on their way, and
// in the end the same frame, bit for bit, as with everything read.
#include "cli_scenes.hpp"
#include "surfeled_scene.hpp"
#include "test_support.hpp"

#include <pbs/surfels/frame_renderer.hpp>
#include <pbs/surfels/surfel_stream.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>

namespace pbs {
namespace {

using test::ScratchDir;

// The groups drawn as surfels even where they fill much of the view, so that views draw both.
LodOptions lodOptions() {
  LodOptions lod;
  lod.descendExhausted = false;
  return lod;
}

struct Streamed {
  test::SurfeledScene scene;
  SurfelCache cache;
  SurfelStream stream;
  FrameRenderer renderer;
  Streamed(const std::filesystem::path& file, const StreamOptions& options, const LodOptions& lod = lodOptions())
      : scene(test::writtenSurfeledScene(file)),
        cache(file, scene.scene, scene.hierarchy, std::uint64_t(1) << 30),
        stream(cache, scene.scene, scene.hierarchy, lod, options),
        renderer(scene.scene, scene.hierarchy, {.mode = RenderMode::Surfels, .lod = lod}, 160, 120,
                 {.cache = &cache, .stream = &stream}) {}
};

std::uint64_t fileDataBytes(const SurfelCache& cache) {
  std::uint64_t bytes = 0;
  for (std::uint32_t a = 0; a < cache.surfels().arrays.size(); ++a)
    bytes += cache.storedBytes(a, cache.surfels().arrays[a].size());
  return bytes;
}

TEST(SurfelStream, DrawsNothingBeforeTheTablesAndConvergesToTheWholeFilesFrame) {
  ScratchDir scratch;
  Streamed s(scratch / "g.surfels", {.bytesPerSecond = 1000.0, .order = StreamOrder::Prefixes});
  const Camera camera = test::approachCameras(s.scene, 4)[2];  // geometry and long prefixes
  ASSERT_GT(s.cache.tablesBytes(), 200u);
  s.stream.advance(camera, 0.1);  // 100 bytes: not the tables yet
  EXPECT_FALSE(s.stream.stats().tablesArrived);
  EXPECT_EQ(s.stream.stats().missingBytes, s.cache.tablesBytes()) << "the tables come first";
  FrameResult empty = s.renderer.render(camera);
  for (const glm::vec4& pixel : empty.image) ASSERT_EQ(pixel.a, 0.0f) << "nothing drawn before the tables";

  // Long enough for every byte of the file and the meshes.
  std::uint64_t meshTotal = 0;
  for (const Mesh& mesh : s.scene.scene.meshes) meshTotal += meshBytes(mesh);
  s.stream.advance(camera, double(s.cache.tablesBytes() + fileDataBytes(s.cache) + meshTotal) / 1000.0);
  EXPECT_EQ(s.stream.stats().missingBytes, 0u);
  EXPECT_EQ(s.stream.stats().missingPixels, 0.0);
  const FrameResult streamed = s.renderer.render(camera);

  const SceneSurfels whole = loadSceneSurfels(scratch / "g.surfels", s.scene.scene, s.scene.hierarchy);
  FrameRenderer reference(s.scene.scene, s.scene.hierarchy, {.mode = RenderMode::Surfels, .lod = lodOptions()}, 160,
                          120, {.surfels = &whole});
  const FrameResult expected = reference.render(camera);
  ASSERT_GT(expected.stats.triangles, 0u);
  ASSERT_GT(expected.stats.surfels, 0u);
  EXPECT_TRUE(test::sameBits(streamed.image, expected.image));
  EXPECT_EQ(streamed.stats.triangles, expected.stats.triangles);
  EXPECT_EQ(streamed.stats.surfels, expected.stats.surfels);
}

TEST(SurfelStream, NeverMoreBytesThanTheLinkCarriedAndTheErrorFallsAsTheyArrive) {
  ScratchDir scratch;
  const double rate = 20000.0;
  Streamed s(scratch / "g.surfels", {.bytesPerSecond = rate, .order = StreamOrder::Prefixes});
  const Camera camera = test::approachCameras(s.scene, 4)[1];
  std::uint64_t before = 0;
  std::size_t drawnBefore = 0;
  bool grew = false;
  for (int step = 1; step <= 40; ++step) {
    s.stream.advance(camera, 0.05);
    const StreamStats& stats = s.stream.stats();
    EXPECT_LE(double(stats.bytes), rate * stats.seconds + 1e-6) << "step " << step;
    EXPECT_GE(stats.bytes, before);
    EXPECT_EQ(stats.bytes, (stats.tablesArrived ? s.cache.tablesBytes() : 0) + stats.surfelBytes + stats.meshBytes);
    before = stats.bytes;
    const LodDraws wanted = traverseLod(s.scene.scene, s.scene.hierarchy, s.cache.surfels(), camera, lodOptions());
    const LodDraws drawn = s.stream.arrived(wanted, camera);
    for (const LodDraws::Surfels& d : drawn.surfels) {
      const SplatArray& array = s.cache.surfels().arrays[d.array];
      EXPECT_LE(d.count, array.loaded()) << "only what has arrived";
      EXPECT_GT(d.count, 0u);
    }
    for (std::uint32_t node : drawn.geometryNodes) EXPECT_GE(s.scene.scene.nodes[node].mesh, 0);
    grew = grew || drawn.surfelCount + drawn.triangles > drawnBefore;
    drawnBefore = drawn.surfelCount + drawn.triangles;
  }
  EXPECT_TRUE(grew);
  EXPECT_TRUE(s.stream.stats().tablesArrived);
}

TEST(SurfelStream, ShortPrefixesDrawLargerDiscs) {
  ScratchDir scratch;
  Streamed s(scratch / "g.surfels", {.bytesPerSecond = 1e9, .order = StreamOrder::Prefixes});
  const Camera camera = test::approachCameras(s.scene, 4)[1];
  s.stream.advance(camera, 1.0);
  const LodDraws wanted = traverseLod(s.scene.scene, s.scene.hierarchy, s.cache.surfels(), camera, lodOptions());
  ASSERT_FALSE(wanted.surfels.empty());
  // Pretend the first draw asks for more than its array holds: the cut keeps the loaded surfels and
  // grows the disc to close the surface with them.
  LodDraws asking = wanted;
  LodDraws::Surfels& first = asking.surfels.front();
  const SplatArray& array = s.cache.surfels().arrays[first.array];
  ASSERT_GT(array.loaded(), 0u);
  ASSERT_GT(array.packing, 0.0);
  first.count = std::uint32_t(array.loaded()) + 1000;
  first.radius = array.spacing(first.count);
  first.pointSize = 1.0;
  const LodDraws cut = s.stream.arrived(asking, camera);
  ASSERT_FALSE(cut.surfels.empty());
  EXPECT_EQ(cut.surfels.front().count, array.loaded());
  EXPECT_GT(cut.surfels.front().radius, first.radius);
  EXPECT_DOUBLE_EQ(cut.surfels.front().pointSize, cut.surfels.front().radius / first.radius);
}

TEST(SurfelStream, WholeArraysAreDrawnOnlyOnceComplete) {
  ScratchDir scratch;
  Streamed s(scratch / "g.surfels", {.bytesPerSecond = 100000.0, .order = StreamOrder::WholeArrays});
  const Camera camera = test::approachCameras(s.scene, 4)[1];
  std::size_t sawDraws = 0;
  for (int step = 0; step < 40; ++step) {
    s.stream.advance(camera, 0.05);
    const LodDraws wanted = traverseLod(s.scene.scene, s.scene.hierarchy, s.cache.surfels(), camera, lodOptions());
    for (const SplatArray& array : s.cache.surfels().arrays)
      EXPECT_TRUE(array.loaded() == 0 || array.loaded() == array.size()) << "an array arrives whole";
    for (const LodDraws::Surfels& d : s.stream.arrived(wanted, camera).surfels) {
      EXPECT_EQ(s.cache.surfels().arrays[d.array].loaded(), s.cache.surfels().arrays[d.array].size());
      ++sawDraws;
    }
  }
  EXPECT_GT(sawDraws, 0u);
}

TEST(SurfelStream, SurfelsStandInForMeshesStillOnTheirWay) {
  ScratchDir scratch;
  const double rate = 1000.0;
  Streamed s(scratch / "g.surfels", {.bytesPerSecond = rate, .order = StreamOrder::Prefixes});
  const Camera camera = test::approachCameras(s.scene, 4).back();
  const LodDraws wanted = traverseLod(s.scene.scene, s.scene.hierarchy, s.cache.surfels(), camera, lodOptions());
  ASSERT_FALSE(wanted.geometryNodes.empty()) << "the near view draws geometry";
  // The tables and half a byte: nothing else fits.
  s.stream.advance(camera, (double(s.cache.tablesBytes()) + 0.5) / rate);
  ASSERT_TRUE(s.stream.stats().tablesArrived);
  ASSERT_EQ(s.stream.stats().meshBytes, 0u);
  // As if every array had come in first: the geometry nodes' meshes are still missing.
  for (std::uint32_t a = 0; a < s.cache.surfels().arrays.size(); ++a)
    s.cache.loadPrefix(a, s.cache.surfels().arrays[a].size());
  const LodDraws drawn = s.stream.arrived(wanted, camera);
  EXPECT_TRUE(drawn.geometryNodes.empty()) << "no mesh has arrived";
  EXPECT_EQ(drawn.triangles, 0u);
  bool standIn = false;
  for (const LodDraws::Surfels& d : drawn.surfels) {
    const bool inWanted = std::any_of(wanted.surfels.begin(), wanted.surfels.end(),
                                      [&](const LodDraws::Surfels& w) { return w.node == d.node; });
    standIn = standIn || !inWanted;
  }
  EXPECT_TRUE(standIn) << "a node above the missing geometry draws its surfels instead";
}

TEST(SurfelStream, BadClockOrBandwidthIsRefused) {
  ScratchDir scratch;
  Streamed s(scratch / "g.surfels", {.bytesPerSecond = 1000.0, .order = StreamOrder::Prefixes});
  EXPECT_THROW(s.stream.advance(test::approachCameras(s.scene, 2).front(), -1.0), std::invalid_argument);
  EXPECT_THROW(SurfelStream(s.cache, s.scene.scene, s.scene.hierarchy, {}, {.bytesPerSecond = 0.0}),
               std::invalid_argument);
  EXPECT_EQ(streamOrderFromName("arrays"), StreamOrder::WholeArrays);
  EXPECT_FALSE(streamOrderFromName("bytes").has_value());
}

// From the command line: frames refine as bytes arrive, the same bits with one thread or two.
TEST(SurfelStreamCli, RenderStreamsFramesThatRefineTheSameForAnyThreadCount) {
  ScratchDir scratch;
  const auto [scene, surfels] = test::groupsWithSurfels(scratch);
  const std::string common = "render " + scene + " --surfels " + surfels +
                             " --size 160x120 --path approach --frames 8 --stream 0.05 --stream-fps 10 --json -o ";
  const test::CommandResult one = test::runPbs(common + "'" + (scratch / "one").string() + "' --threads 1");
  const test::CommandResult two = test::runPbs(common + "'" + (scratch / "two").string() + "' --threads 2");
  ASSERT_EQ(one.status, 0) << one.err;
  ASSERT_EQ(two.status, 0) << two.err;
  const nlohmann::json report = nlohmann::json::parse(one.out);
  std::uint64_t before = 0;
  for (std::size_t f = 0; f < 8; ++f) {
    const std::string name = "frame_000" + std::to_string(f) + ".png";
    EXPECT_EQ(test::readFile(scratch / "one" / name), test::readFile(scratch / "two" / name)) << name;
    const nlohmann::json& frame = report["frames"][f];
    EXPECT_DOUBLE_EQ(frame["stream_seconds"].get<double>(), double(f + 1) / 10.0);
    const std::uint64_t bytes = frame["stream_bytes"].get<std::uint64_t>();
    EXPECT_LE(double(bytes), 0.05e6 * double(f + 1) / 10.0 + 1e-6);
    EXPECT_GE(bytes, before);
    before = bytes;
  }
  EXPECT_GT(before, 0u);
  const test::CommandResult noFile = test::runPbs("render " + scene + " --stream 1");
  EXPECT_NE(noFile.status, 0);
  EXPECT_NE(noFile.err.find("--surfels"), std::string::npos) << noFile.err;
  const test::CommandResult exact =
      test::runPbs("render " + scene + " --surfels " + surfels + " --mode exact --stream 1");
  EXPECT_NE(exact.status, 0);
  EXPECT_NE(exact.err.find("not with --mode exact"), std::string::npos) << exact.err;
  EXPECT_EQ(test::runPbs(common + "x --stream-order bytes").status, 2);
}

}  // namespace
}  // namespace pbs
