// Surfelize split over machines: `pbs surfelize --shard I/N` parts that `pbs merge` puts together into the
// one-machine file byte for byte, every refusal of merge, the --shard values refused, the index from a
// scheduler's variable, and `pbs render --shard` filling the folder an unsharded run fills.
#include "cli_scenes.hpp"
#include "shard_runs.hpp"
#include "test_fixtures.hpp"
#include "test_support.hpp"

#include <pbs/scene/generate.hpp>
#include <pbs/scene/gltf_export.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace pbs {
namespace {

using test::expectShardsMergeToTheSingleRun;
using test::makePart;
using test::quoted;
using test::quotedAll;
using test::runPbs;
using test::ScratchDir;

// A generated city (what `pbs generate city` makes) of three box prototypes, 4 × 4 × 4 leaves: arrays at
// three levels, some shared between instances.
std::string cityFile(const ScratchDir& scratch) {
  std::vector<Scene> prototypes;
  for (std::uint32_t n : {6u, 10u, 14u})
    prototypes.push_back(test::sceneOf(test::tessellatedBox(n), {glm::dmat4(1.0)}));
  writeGlb(generateCity(prototypes, {.levels = 3, .fanout = 4, .seed = 3}), scratch / "city.glb");
  return quoted(scratch / "city.glb");
}

constexpr const char* kSmall = " --min-triangles 2000 --resolution 32 --max-surfels 500 --quiet";

TEST(SurfelizeShards, CityMergesToTheSingleRunFor1237Shards) {
  ScratchDir scratch;
  expectShardsMergeToTheSingleRun(cityFile(scratch), scratch, kSmall);
}

// Captures of triangles only: no array needs another, so the shards split the arrays between them.
TEST(SurfelizeShards, CityOfTriangleCapturesMergesToTheSingleRunFor1237Shards) {
  ScratchDir scratch;
  const std::string city = cityFile(scratch);
  const std::string options = std::string(kSmall) + " --capture-from triangles";
  expectShardsMergeToTheSingleRun(city, scratch, options);
  const test::CommandResult plan = runPbs("surfelize " + city + " -o x --shard-plan 3 --json" + options);
  ASSERT_EQ(plan.status, 0) << plan.err;
  const nlohmann::json shards = nlohmann::json::parse(plan.out)["per_shard"];
  for (const nlohmann::json& shard : shards) EXPECT_GT(shard["arrays_held"].get<int>(), 0) << plan.out;
}

// The index from a job array's variable (Slurm's, Kubernetes'), the same part as the index given.
TEST(SurfelizeShards, AutoTakesTheIndexFromTheSchedulersVariable) {
  ScratchDir scratch;
  const std::string city = cityFile(scratch);
  const std::string given = test::readFile(makePart(city, scratch.path(), 1, 3, kSmall));
  for (const char* variable : {"SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"}) {
    ::setenv(variable, "1", 1);
    const std::filesystem::path part = scratch / (std::string(variable) + ".surfels");
    const test::CommandResult made =
        runPbs("surfelize " + city + " -o " + quoted(part) + " --shard auto/3 --threads 1" + kSmall);
    ::unsetenv(variable);
    ASSERT_EQ(made.status, 0) << made.err;
    EXPECT_TRUE(test::readFile(part) == given) << variable << ": the part of shard 1/3, whatever the threads";
  }
}

TEST(SurfelizeShards, BadShardValuesGetOneErrorLine) {
  ScratchDir scratch;
  const std::string groups = test::groupsFile(scratch);
  const auto refused = [&](const std::string& shard, const std::string& why) {
    const test::CommandResult run =
        runPbs("surfelize " + groups + " -o " + quoted(scratch / "x.surfels") + " --shard " + shard);
    EXPECT_EQ(run.status, 2) << shard;
    EXPECT_EQ(run.err.rfind("error: --shard", 0), 0u) << run.err;
    EXPECT_NE(run.err.find(why), std::string::npos) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_FALSE(std::filesystem::exists(scratch / "x.surfels"));
  };
  refused("0/0", "expected I/N");
  refused("3/2", "must be below the count");
  refused("2/2", "must be below the count");
  refused("banana", "expected I/N");
  refused("1/", "expected I/N");
  refused("-1/2", "expected I/N");
  refused("1/2x", "expected I/N");
  refused("0/4000000000", "4000000000 shards: at most 1000000");
  ::unsetenv("SLURM_ARRAY_TASK_ID");
  ::unsetenv("JOB_COMPLETION_INDEX");
  refused("auto/2", "none of $SLURM_ARRAY_TASK_ID");
  ::setenv("SLURM_ARRAY_TASK_ID", "first", 1);
  refused("auto/2", "$SLURM_ARRAY_TASK_ID is 'first'");
  ::setenv("SLURM_ARRAY_TASK_ID", "5", 1);
  refused("auto/2", "shard 5 of 2");
  ::unsetenv("SLURM_ARRAY_TASK_ID");
}

// Parts of the city, 3 shards, for the refusals below.
struct CityParts {
  ScratchDir scratch;
  std::string city = cityFile(scratch);
  std::vector<std::filesystem::path> parts = {makePart(city, scratch.path(), 0, 3, kSmall),
                                              makePart(city, scratch.path(), 1, 3, kSmall),
                                              makePart(city, scratch.path(), 2, 3, kSmall)};
  std::filesystem::path output = scratch / "merged.surfels";

  // Merging `files` is refused with one error line holding every one of `expected`, and no output.
  void expectRefused(const std::vector<std::filesystem::path>& files, const std::vector<std::string>& expected) {
    const test::CommandResult merge = runPbs("merge" + quotedAll(files) + " -o " + quoted(output));
    EXPECT_EQ(merge.status, 1) << merge.err;
    EXPECT_EQ(merge.err.rfind("error: ", 0), 0u) << merge.err;
    EXPECT_EQ(std::count(merge.err.begin(), merge.err.end(), '\n'), 1) << merge.err;
    for (const std::string& text : expected) EXPECT_NE(merge.err.find(text), std::string::npos) << merge.err;
    EXPECT_FALSE(std::filesystem::exists(output)) << "nothing written";
    for (const auto& entry : std::filesystem::directory_iterator(scratch.path()))
      EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << "no temporary left: " << entry.path();
  }
};

TEST(MergeRefuses, AMissingShard) {
  CityParts city;
  city.expectRefused({city.parts[0], city.parts[2]}, {city.output.string(), "shard 1/3", "missing"});
}

TEST(MergeRefuses, AShardGivenTwice) {
  CityParts city;
  const std::filesystem::path copy = city.scratch / "copy-of-2.surfels";
  std::filesystem::copy_file(city.parts[2], copy);
  city.expectRefused({city.parts[0], city.parts[1], city.parts[2], copy}, {copy.string(), "shard 2/3", "given twice"});
}

TEST(MergeRefuses, AShardOfAnotherScene) {
  CityParts city;
  const std::filesystem::path groups = makePart(test::groupsFile(city.scratch), city.scratch / "", 1, 3, kSmall);
  city.expectRefused({city.parts[0], groups, city.parts[2]}, {groups.string(), "shard 1/3", "another scene"});
}

TEST(MergeRefuses, AShardOfOtherOptions) {
  CityParts city;
  const std::filesystem::path other = city.scratch / "other-options.surfels";
  const test::CommandResult made =
      runPbs("surfelize " + city.city + " -o " + quoted(other) + " --shard 1/3" + kSmall + " --seed 7");
  ASSERT_EQ(made.status, 0) << made.err;
  city.expectRefused({city.parts[0], other, city.parts[2]}, {other.string(), "shard 1/3", "other options", "seed 7"});
}

TEST(MergeRefuses, AShardOfAnotherPlan) {
  CityParts city;
  // Shard 1 of 2 and of another capture source: options the file header does not hold, the plan does.
  const std::filesystem::path ofTwo = makePart(city.city, city.scratch.path(), 1, 2, kSmall);
  city.expectRefused({city.parts[0], ofTwo, city.parts[2]}, {ofTwo.string(), "shard 1/2", "another plan"});
  const std::filesystem::path triangles = city.scratch / "triangles.surfels";
  const test::CommandResult made = runPbs("surfelize " + city.city + " -o " + quoted(triangles) + " --shard 1/3" +
                                          kSmall + " --capture-from triangles");
  ASSERT_EQ(made.status, 0) << made.err;
  city.expectRefused({city.parts[0], triangles, city.parts[2]}, {triangles.string(), "shard 1/3", "another plan"});
}

TEST(MergeRefuses, ATruncatedPart) {
  CityParts city;
  const std::string bytes = test::readFile(city.parts[1]);
  test::writeFile(city.parts[1], bytes.substr(0, bytes.size() - 100));
  city.expectRefused(city.parts, {city.parts[1].string(), "truncated"});
}

TEST(MergeRefuses, APartWithABadChecksum) {
  CityParts city;
  std::string bytes = test::readFile(city.parts[2]);
  bytes[bytes.size() - 200] = char(bytes[bytes.size() - 200] ^ 0x10);  // in the data of its last array
  test::writeFile(city.parts[2], bytes);
  city.expectRefused(city.parts, {city.parts[2].string(), "checksum mismatch"});
}

TEST(MergeRefuses, AWholeFileForAPart) {
  CityParts city;
  const std::filesystem::path whole = city.scratch / "whole.surfels";
  ASSERT_EQ(runPbs("surfelize " + city.city + " -o " + quoted(whole) + kSmall).status, 0);
  city.expectRefused({city.parts[0], whole, city.parts[2]}, {whole.string(), "not a shard's part"});
}

TEST(MergeRefuses, AndLeavesAnOldFileAsItWas) {
  CityParts city;
  test::writeFile(city.output, "the old file");
  const test::CommandResult merge =
      runPbs("merge" + quotedAll({city.parts[0], city.parts[1]}) + " -o " + quoted(city.output));
  EXPECT_EQ(merge.status, 1);
  EXPECT_EQ(test::readFile(city.output), "the old file");
}

// Frames f with f mod 3 = I, three shards into one folder: the folder of one unsharded run.
TEST(RenderShards, ThreeShardsFillTheFolderOneRunFills) {
  ScratchDir scratch;
  const auto [scene, surfels] = test::groupsWithSurfels(scratch);
  const std::string common = "render " + scene + " --surfels " + surfels + " --frames 7 --size 64x48 -o ";
  const test::CommandResult single = runPbs(common + quoted(scratch / "single") + " --json");
  ASSERT_EQ(single.status, 0) << single.err;
  const nlohmann::json singleFrames = nlohmann::json::parse(single.out)["frames"];
  for (int shard = 0; shard < 3; ++shard) {
    const test::CommandResult part =
        runPbs(common + quoted(scratch / "sharded") + " --shard " + std::to_string(shard) + "/3 --json");
    ASSERT_EQ(part.status, 0) << part.err;
    const nlohmann::json frames = nlohmann::json::parse(part.out)["frames"];
    EXPECT_EQ(frames.size(), shard == 0 ? 3u : 2u) << "frames " << shard << ", +3, …";
    // Each drawn by the drawer the single run chose, having passed over the other shards' frames.
    for (std::size_t i = 0; i < frames.size(); ++i)
      EXPECT_EQ(frames[i]["geometry"], singleFrames[std::size_t(shard) + 3 * i]["geometry"]) << shard << ", " << i;
  }
  std::size_t frames = 0;
  for (const auto& entry : std::filesystem::directory_iterator(scratch / "single")) {
    ++frames;
    EXPECT_TRUE(test::readFile(entry.path()) == test::readFile(scratch / "sharded" / entry.path().filename()))
        << entry.path().filename();
  }
  EXPECT_EQ(frames, 7u);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(scratch / "sharded"), {}), 7);

  const test::CommandResult noFrames =
      runPbs("render " + scene + " --surfels " + surfels + " --shard 0/2 -o " + quoted(scratch / "one.png"));
  EXPECT_EQ(noFrames.status, 2);
  EXPECT_NE(noFrames.err.find("give --frames N"), std::string::npos) << noFrames.err;
  const test::CommandResult streamed = runPbs(common + quoted(scratch / "s") + " --shard 0/2 --stream 1");
  EXPECT_EQ(streamed.status, 2);
  EXPECT_NE(streamed.err.find("not with --stream"), std::string::npos) << streamed.err;
}

}  // namespace
}  // namespace pbs
