// `pbs figure`: the scaling figure on a tiny mesh (its CSV columns, cities growing, surfels drawing
// less than exact at the largest), the views figure on a small scene (the sheet's size, near views
// drawing more triangles than far ones), and clear errors for what the scaling series cannot do.
#include "cli_scenes.hpp"
#include "output_files.hpp"
#include "test_fixtures.hpp"
#include "test_support.hpp"

#include <pbs/scene/gltf_export.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace pbs {
namespace {

using test::pngSize;
using test::readCsv;
using test::ScratchDir;

// A 1,200-triangle box as `scratch`/box.glb, quoted: cities of it stay small enough for a test.
std::string boxFile(const ScratchDir& scratch) {
  writeGlb(test::sceneOf(test::tessellatedBox(10), {glm::dmat4(1.0)}), scratch / "box.glb");
  return "'" + (scratch / "box.glb").string() + "'";
}

TEST(FigureCli, ScalingMeasuresGrowingCitiesInBothModes) {
  ScratchDir scratch;
  const std::filesystem::path out = scratch / "scaling";
  // 12 and 144 boxes (14,400 and 172,800 triangles); the next city, 2 M, is over the cap.
  const test::CommandResult run = test::runPbs("figure scaling --mesh " + boxFile(scratch) + " -o '" + out.string() +
                                               "' --max-triangles 200000 --frames 2 --size 160x90 --quiet");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(run.err.empty()) << "--quiet: " << run.err;

  const test::CsvTable csv = readCsv(out / "scaling.csv");
  for (const char* column : {"triangles", "instances", "surfelize_seconds", "exact_ms", "surfels_ms", "surfels_drawn",
                             "triangles_drawn", "exact_triangles_drawn", "psnr", "ssim"})
    EXPECT_NE(std::find(csv.columns.begin(), csv.columns.end(), column), csv.columns.end()) << column;
  ASSERT_EQ(csv.rows.size(), 2u);
  EXPECT_EQ(csv.rows[0].number("triangles"), 14'400);
  EXPECT_EQ(csv.rows[1].number("triangles"), 172'800);
  EXPECT_EQ(csv.rows[1].number("instances"), 144);
  for (std::size_t row = 0; row < csv.rows.size(); ++row) {
    if (row > 0) {
      EXPECT_GT(csv.rows[row].number("triangles"), csv.rows[row - 1].number("triangles"));
    }
    for (const char* time : {"surfelize_seconds", "exact_ms", "surfels_ms"}) {
      EXPECT_TRUE(std::isfinite(csv.rows[row].number(time))) << time;
      EXPECT_GT(csv.rows[row].number(time), 0.0) << time;
    }
  }
  const std::size_t last = csv.rows.size() - 1;
  EXPECT_GT(csv.rows[last].number("surfels_drawn"), 0.0);
  EXPECT_LT(csv.rows[last].number("surfels_drawn") + csv.rows[last].number("triangles_drawn"),
            csv.rows[last].number("exact_triangles_drawn"));

  const auto json = nlohmann::json::parse(test::readFile(out / "scaling.json"));
  EXPECT_EQ(json["cities"].size(), 2u);
  const std::string svg = test::readFile(out / "scaling.svg");
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find(">exact<"), std::string::npos) << "the legend names both modes";
  EXPECT_NE(svg.find(">surfels<"), std::string::npos);
}

TEST(FigureCli, ScalingErrorsAreOneLine) {
  ScratchDir scratch;
  const std::string output = " -o '" + (scratch / "out").string() + "' --quiet";
  const test::CommandResult tooSmall =
      test::runPbs("figure scaling --mesh " + boxFile(scratch) + " --max-triangles 1000" + output);
  EXPECT_EQ(tooSmall.status, 1);
  EXPECT_EQ(tooSmall.err.rfind("error: the smallest city", 0), 0u) << tooSmall.err;

  // Without --mesh the default comes from the shared scenes; where they are not, the error says so.
  const char* previous = std::getenv("PBS_SCENES");
  const std::string saved = previous ? previous : "";
  setenv("PBS_SCENES", (scratch / "no-scenes").c_str(), 1);
  const test::CommandResult noScenes = test::runPbs("figure scaling" + output);
  if (previous)
    setenv("PBS_SCENES", saved.c_str(), 1);
  else
    unsetenv("PBS_SCENES");
  EXPECT_EQ(noScenes.status, 1);
  EXPECT_EQ(noScenes.err.rfind("error: ", 0), 0u) << noScenes.err;
  EXPECT_NE(noScenes.err.find("--mesh"), std::string::npos) << noScenes.err;
  EXPECT_EQ(std::count(noScenes.err.begin(), noScenes.err.end(), '\n'), 1) << noScenes.err;
}

TEST(FigureCli, ViewsSheetAndNearDrawsMoreGeometryThanFar) {
  ScratchDir scratch;
  const auto [scene, surfels] = test::groupsWithSurfels(scratch);
  const std::filesystem::path out = scratch / "views";
  const test::CommandResult run =
      test::runPbs("figure views " + scene + " --surfels " + surfels + " -o '" + out.string() +
                   "' --size 320x200 --overdraw 4 --quiet");  // the small arrays last at 4, not 16
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(run.err.empty()) << "--quiet: " << run.err;

  EXPECT_EQ(pngSize(out / "views.png"), std::make_pair(3u * 320u, 3u * 200u))
      << "3 views × exact | surfels | difference";
  const test::CsvTable csv = readCsv(out / "views.csv");
  ASSERT_EQ(csv.rows.size(), 3u);
  EXPECT_EQ(csv.rows[0].fields.at("view"), "near");
  EXPECT_EQ(csv.rows[2].fields.at("view"), "far");
  EXPECT_GT(csv.rows[0].number("distance"), 0.0);
  EXPECT_LT(csv.rows[0].number("distance"), csv.rows[1].number("distance"));
  EXPECT_LT(csv.rows[1].number("distance"), csv.rows[2].number("distance"));
  EXPECT_GT(csv.rows[0].number("triangles_drawn"), csv.rows[2].number("triangles_drawn"));
  EXPECT_GT(csv.rows[2].number("surfels_drawn"), 0.0) << "far away, surfels stand in for geometry";
  for (std::size_t row = 0; row < 3; ++row) {
    // Infinite where the view draws only geometry (an array too short for the group is descended into):
    // the same picture as the exact one.
    EXPECT_FALSE(std::isnan(csv.rows[row].number("psnr"))) << csv.rows[row].fields.at("view");
    EXPECT_GT(csv.rows[row].number("exact_ms"), 0.0);
    EXPECT_GT(csv.rows[row].number("surfels_ms"), 0.0);
  }
  const auto json = nlohmann::json::parse(test::readFile(out / "views.json"));
  EXPECT_EQ(json["views"].size(), 3u);
}
// The stream figure on the groups: at the faster link the prefixes arrive within the plotted time and
// the error falls to that of the frame with everything loaded; no series gets more bytes than its link.
TEST(FigureCli, StreamErrorFallsAsPrefixesArrive) {
  ScratchDir scratch;
  const auto [scene, surfels] = test::groupsWithSurfels(scratch);
  const std::filesystem::path out = scratch / "stream";
  const test::CommandResult run =
      test::runPbs("figure stream " + scene + " --surfels " + surfels + " -o '" + out.string() +
                   "' --size 160x100 --orbit 30,20,1.5 --bandwidths 0.5,0.02 --seconds 2 --steps 8 "
                   "--reference-samples 4 --exhausted grow --quiet");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(pngSize(out / "stream.png"), std::make_pair(3u * 160u, 3u * 100u))
      << "3 times × prefixes | arrays | reference";
  EXPECT_EQ(test::readFile(out / "stream.svg").rfind("<svg", 0), 0u);
  const test::CsvTable csv = readCsv(out / "stream.csv");
  ASSERT_EQ(csv.rows.size(), 2u * 2u * 8u) << "two bandwidths × two orders × 8 steps";
  EXPECT_EQ(csv.rows[0].number("megabytes_per_second"), 0.02) << "slowest first";
  const auto json = nlohmann::json::parse(test::readFile(out / "stream.json"));
  const double loaded = json["every_prefix_loaded"]["flip_foreground"].get<double>();
  for (const auto& series : json["series"]) {
    const auto& steps = series["steps"];
    const double rate = series["megabytes_per_second"].get<double>() * 1e6;
    for (const auto& step : steps) EXPECT_LE(step["bytes"].get<double>(), rate * step["seconds"].get<double>() + 1e-6);
    EXPECT_LE(steps.back()["flip_foreground"].get<double>(), steps.front()["flip_foreground"].get<double>());
    if (series["megabytes_per_second"].get<double>() == 0.5) {
      EXPECT_EQ(steps.back()["missing_bytes"].get<std::uint64_t>(), 0u) << series["order"];
      EXPECT_NEAR(steps.back()["flip_foreground"].get<double>(), loaded, 1e-12) << series["order"];
    }
  }
}

}  // namespace
}  // namespace pbs
