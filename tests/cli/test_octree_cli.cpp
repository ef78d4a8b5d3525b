// A flat scene end to end: surfelize rebuilds it as a loose octree (asked for, or because one node draws
// a mesh above --octree-above), records it in the .surfels file, and every command that reads the file
// rebuilds the same hierarchy; a scene that is not the one the octree was made of is refused, naming it.
#include "test_support.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace pbs {
namespace {

using test::runPbs;
using test::ScratchDir;

struct FlatScene {
  ScratchDir scratch;
  std::string terrain = test::quoted(scratch / "terrain.glb");

  FlatScene() {
    const test::CommandResult made = runPbs("generate terrain --triangles 20000 -o " + terrain);
    EXPECT_EQ(made.status, 0) << made.err;
  }
  std::string file(const std::string& name) const { return test::quoted(scratch / name); }
  nlohmann::json surfelize(const std::string& name, const std::string& arguments) const {
    const test::CommandResult run =
        runPbs("surfelize " + terrain + " -o " + file(name) + " --min-triangles 2000 --json " + arguments);
    EXPECT_EQ(run.status, 0) << run.err;
    return run.status == 0 ? nlohmann::json::parse(run.out) : nlohmann::json();
  }
};

TEST(OctreeCli, AFlatMeshGetsArraysAtEveryLevelAndRendersFromTheFile) {
  const FlatScene flat;
  const nlohmann::json own = flat.surfelize("own.surfels", "");
  EXPECT_EQ(own["octree_leaf_triangles"], 0) << "20,000 triangles are below the default of a million";
  EXPECT_EQ(own["arrays"], 1);
  const nlohmann::json octree = flat.surfelize("octree.surfels", "--octree-above 10000 --octree-leaf 1000");
  EXPECT_EQ(octree["octree_leaf_triangles"], 1000);
  EXPECT_GT(octree["arrays"].get<int>(), 4) << "the root and the octree's inner levels each get arrays";
  EXPECT_EQ(flat.surfelize("asked.surfels", "--octree --octree-leaf 1000")["arrays"], octree["arrays"]);
  EXPECT_EQ(flat.surfelize("never.surfels", "--octree-above 0")["arrays"], 1);

  // From afar the octree's nodes draw their prefixes; the file's hierarchy is rebuilt to read them.
  const test::CommandResult far = runPbs("render " + flat.terrain + " --surfels " + flat.file("octree.surfels") +
                                         " --orbit 30,40,6 --size 160x120 --json -o " + flat.file("far.png"));
  ASSERT_EQ(far.status, 0) << far.err;
  const nlohmann::json frame = nlohmann::json::parse(far.out);
  EXPECT_GT(frame["surfels"].get<int>(), 0);
  const test::CommandResult eval = runPbs(
      "eval " + flat.terrain + " --surfels " + flat.file("octree.surfels") +
      " --size 96x64 --frames 1 --peers exact=1 --reference-samples 4 --sweep surfels --quiet -o " + flat.file("eval"));
  EXPECT_EQ(eval.status, 0) << eval.err;
}

TEST(OctreeCli, AnotherSceneIsRefusedNamingTheOctree) {
  const FlatScene flat;
  flat.surfelize("octree.surfels", "--octree --octree-leaf 1000");
  const std::string other = flat.file("other.glb");
  ASSERT_EQ(runPbs("generate terrain --triangles 20000 --seed 2 -o " + other).status, 0);
  const test::CommandResult run = runPbs("render " + other + " --surfels " + flat.file("octree.surfels") +
                                         " --size 64x48 -o " + flat.file("x.png"));
  EXPECT_EQ(run.status, 1);
  EXPECT_EQ(run.err.rfind("error: ", 0), 0u) << run.err;
  EXPECT_NE(run.err.find("as a loose octree of leaves of at most 1000 triangles"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace pbs
