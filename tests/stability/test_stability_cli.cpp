// The `pbs` command line on stiff and non-finite input: one line starting "error:" that names the file
// and the element, a non-zero status, no output written, never a crash; and finite JSON where it works.
#include "cli_scenes.hpp"
#include "gltf_test_files.hpp"
#include "test_support.hpp"

#include "forged_surfel_file.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>

namespace pbs {
namespace {

using test::runPbs;
using test::ScratchDir;

// Built by append: GCC 12's -Wrestrict misfires on "'" + std::string.
std::string quoted(const std::filesystem::path& path) { return std::string("'").append(path.string()).append("'"); }

// Status 1 and exactly one line on stderr: "error: FILE: ELEMENT: …" holding `problem`.
void expectErrorLine(const test::CommandResult& result, const std::filesystem::path& file, const std::string& element,
                     const std::string& problem) {
  EXPECT_EQ(result.status, 1) << result.err;
  EXPECT_TRUE(result.err.starts_with("error: " + file.string() + ": " + element + ": ")) << result.err;
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
  EXPECT_NE(result.err.find(problem), std::string::npos) << result.err;
}

// Every number in `json` (recursively) is finite; JSON itself cannot hold NaN, so nlohmann writes
// null for one, and this also rejects a document that does not parse.
void expectFiniteJson(const std::string& text) {
  const nlohmann::json json = nlohmann::json::parse(text);
  const std::function<void(const nlohmann::json&)> visit = [&](const nlohmann::json& j) {
    EXPECT_TRUE(!j.is_number_float() || std::isfinite(j.get<double>())) << text;
    if (j.is_structured()) {
      for (const auto& item : j) visit(item);
    }
  };
  visit(json);
}

// The triangle file with vertex 1's normal (or uv) NaN, as raw bytes in the binary chunk.
test::GltfBuilder triangleWithNaNIn(const char* semantic) {
  test::GltfBuilder b = test::triangleFile();
  const bool uv = std::string(semantic) == "TEXCOORD_0";
  std::vector<float> values(uv ? 6 : 9, 0.0f);
  values[uv ? 2 : 3] = std::numeric_limits<float>::quiet_NaN();
  b.json["meshes"][0]["primitives"][0]["attributes"][semantic] =
      b.addAccessor(values, test::kFloat, uv ? "VEC2" : "VEC3");
  return b;
}

// Expected: NaN in a normal or a uv, and node transforms whose product overflows, stop `pbs info` and
// `pbs surfelize` with one error line naming the file and the accessor or node; nothing is written.
TEST(StabilityCli, NonFiniteSceneInputIsOneErrorLine) {
  ScratchDir scratch;
  test::GltfBuilder overflow = test::triangleFile();
  overflow.json["nodes"][0].erase("mesh");  // only the child's world overflows, not a mesh under the parent
  overflow.json["nodes"][0]["scale"] = {1e200, 1e200, 1e200};
  overflow.json["nodes"][0]["children"] = {1};
  overflow.addNode({{"mesh", 0}, {"scale", {1e200, 1e200, 1e200}}});
  const struct {
    const char* file;
    test::GltfBuilder builder;
    const char* element;
    const char* problem;
  } cases[] = {{"nan-normal.glb", triangleWithNaNIn("NORMAL"), "accessor 2", "element 1 is not finite"},
               {"nan-uv.glb", triangleWithNaNIn("TEXCOORD_0"), "accessor 2", "element 1 is not finite"},
               {"overflow.glb", overflow, "node 1", "world transform is not finite"}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.file);
    const auto file = scratch / c.file;
    test::writeFile(file, c.builder.glb());
    expectErrorLine(runPbs("info " + quoted(file)), file, c.element, c.problem);
    const auto out = scratch / "out.surfels";
    expectErrorLine(runPbs("surfelize " + quoted(file) + " -o " + quoted(out) + " --quiet"), file, c.element,
                    c.problem);
    EXPECT_FALSE(std::filesystem::exists(out));
  }
}

// Expected: a .surfels file holding a NaN coverage (checksums forged to match) stops `pbs render` with
// one error line naming the surfel file and the node using the array; no image is written.
TEST(StabilityCli, SurfelFileWithANaNIsOneErrorLine) {
  ScratchDir scratch;
  const auto [scene, surfelsQuoted] = test::groupsWithSurfels(scratch);
  const auto surfels = scratch / "groups.surfels";
  std::string bytes = test::readFile(surfels);
  stability::forgeArrayValue(bytes, 0, stability::ArrayField::Coverage, std::numeric_limits<double>::quiet_NaN());
  test::writeFile(surfels, bytes);
  const auto image = scratch / "x.png";
  const test::CommandResult result =
      runPbs("render " + scene + " --surfels " + surfelsQuoted + " --size 16x16 -o " + quoted(image));
  expectErrorLine(result, surfels, "node /0/0/0", "coverage is not finite");  // array 0: the boxes (children first)
  EXPECT_FALSE(std::filesystem::exists(image));
}

// Expected: a scene whose only mesh has no triangles (POINTS) is one error line ("scene: nothing to
// draw"); a mesh with no triangles beside one that has them is dropped, and `pbs info --json` reports
// finite JSON for the rest.
TEST(StabilityCli, SceneWithNoTrianglesIsOneErrorLine) {
  ScratchDir scratch;
  test::GltfBuilder points = test::triangleFile();
  points.json["meshes"][0]["primitives"][0]["mode"] = test::kModePoints;
  const auto file = scratch / "points.glb";
  test::writeFile(file, points.glb());
  expectErrorLine(runPbs("info --json " + quoted(file)), file, "scene", "nothing to draw (no triangles)");

  test::GltfBuilder mixed = test::triangleFile();
  mixed.addMesh({{{"attributes", {{"POSITION", 0}}}, {"mode", test::kModePoints}}});
  mixed.addNode({{"mesh", 1}});
  mixed.setScene({0, 1});
  test::writeFile(scratch / "mixed.glb", mixed.glb());
  const test::CommandResult info = runPbs("info --json " + quoted(scratch / "mixed.glb"));
  ASSERT_EQ(info.status, 0) << info.err;
  expectFiniteJson(info.out);
  EXPECT_EQ(nlohmann::json::parse(info.out)["triangles"], 1);
}

// Expected: a one-triangle scene 1e7 from the origin at scale 1e-6 surfelizes with finite JSON, and
// renders at 1×1 and at a thin 16384×1 viewport (exact and surfels modes) with status 0.
TEST(StabilityCli, FarTinyOneTriangleSceneSurfelizesAndRendersAtExtremeSizes) {
  ScratchDir scratch;
  test::GltfBuilder b = test::triangleFile();
  b.json["nodes"][0]["translation"] = {1e7, -1e7, 1e7};
  b.json["nodes"][0]["scale"] = {1e-6, 1e-6, 1e-6};
  const auto file = scratch / "tiny.glb";
  test::writeFile(file, b.glb());
  const auto surfels = scratch / "tiny.surfels";
  const test::CommandResult made =
      runPbs("surfelize " + quoted(file) + " -o " + quoted(surfels) + " --min-triangles 0 --json --quiet");
  ASSERT_EQ(made.status, 0) << made.err;
  expectFiniteJson(made.out);
  for (const char* size : {"1x1", "16384x1"}) {
    for (const std::string mode : {"exact", "surfels"}) {
      SCOPED_TRACE(std::string(size) + " " + mode);
      const auto image = scratch / "tiny.png";
      const test::CommandResult render = runPbs("render " + quoted(file) + " --surfels " + quoted(surfels) +
                                                " --mode " + mode + " --size " + size + " -o " + quoted(image));
      EXPECT_EQ(render.status, 0) << render.err;
      EXPECT_TRUE(std::filesystem::exists(image));
    }
  }
}

}  // namespace
}  // namespace pbs
