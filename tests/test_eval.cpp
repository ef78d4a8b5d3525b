// `pbs eval`: the files it writes (CSV columns, one row per setting and frame, summary keys, one
// marker per setting, the contact sheet's size), zero error for exact against exact, and fewer holes
// with more surfels on a static view.
#include "test_fixtures.hpp"
#include "cli_scenes.hpp"
#include "output_files.hpp"
#include "test_support.hpp"

#include <pbs/scene/gltf_export.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace pbs {
namespace {

using test::groupsWithSurfels;
using test::pngSize;
using test::readCsv;
using test::ScratchDir;

constexpr const char* kHeader =
    "setting,frame,azimuth,seconds,traverse_seconds,raster_seconds,triangles,surfels,rmse,psnr,ssim,hole_fraction";

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// `pbs eval` on the two-groups scene and its surfels, writing into a scratch folder.
struct EvalRun {
  ScratchDir scratch;
  std::string scene, surfels;
  std::filesystem::path out = scratch / "eval";

  EvalRun() { std::tie(scene, surfels) = groupsWithSurfels(scratch); }
  test::CommandResult run(const std::string& arguments) const {
    return test::runPbs("eval " + scene + " --surfels " + surfels + " -o '" + out.string() + "' " + arguments);
  }
  std::vector<test::CsvRow> rows() const { return readCsv(out / "eval.csv").rows; }
};

TEST(EvalCli, WritesOneRowPerSettingAndFrameAndExactHasNoError) {
  const EvalRun eval;
  const test::CommandResult run = eval.run("--size 96x64 --frames 2 --sweep overdraw=1,4 --sweep point=4 --quiet");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(run.err.empty()) << "--quiet: " << run.err;

  const test::CsvTable csv = readCsv(eval.out / "eval.csv");
  const std::vector<test::CsvRow>& rows = csv.rows;
  EXPECT_EQ(csv.header, kHeader);
  const std::vector<std::string> settings = {"exact", "overdraw=1", "overdraw=4", "point=4"};
  ASSERT_EQ(rows.size(), settings.size() * 2);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].fields.at("setting"), settings[i / 2]) << i;
    EXPECT_EQ(rows[i].number("frame"), double(i % 2)) << i;
    EXPECT_GE(rows[i].number("seconds"), 0.0);
    if (settings[i / 2] == "exact") {
      EXPECT_EQ(rows[i].number("rmse"), 0.0);
      EXPECT_EQ(rows[i].fields.at("psnr"), "inf") << "identical images: PSNR is written inf";
      EXPECT_EQ(rows[i].number("ssim"), 1.0);
      EXPECT_EQ(rows[i].number("hole_fraction"), 0.0);
      EXPECT_EQ(rows[i].number("surfels"), 0.0);
      EXPECT_GT(rows[i].number("triangles"), 0.0);
    } else {
      EXPECT_GT(rows[i].number("surfels"), 0.0) << "a far, small scene draws surfels";
      EXPECT_GT(rows[i].number("rmse"), 0.0);
      EXPECT_TRUE(std::isfinite(rows[i].number("psnr")));
    }
  }
  EXPECT_EQ(rows[2].number("azimuth"), 30.0);
  EXPECT_EQ(rows[3].number("azimuth"), 210.0);

  const nlohmann::json summary = nlohmann::json::parse(test::readFile(eval.out / "summary.json"));
  for (const char* key : {"scene", "surfels", "width", "height", "frames", "orbit", "exact_median_seconds", "baseline",
                          "settings", "pareto_front", "contact_sheet"})
    EXPECT_TRUE(summary.contains(key)) << key;
  EXPECT_EQ(summary["baseline"], "overdraw=4");
  ASSERT_EQ(summary["settings"].size(), settings.size());
  for (std::size_t s = 0; s < settings.size(); ++s) {
    const nlohmann::json& entry = summary["settings"][s];
    EXPECT_EQ(entry["name"], settings[s]);
    for (const char* key : {"median_seconds", "median_traverse_seconds", "median_raster_seconds", "median_triangles",
                            "median_surfels", "median_rmse", "worst_rmse", "median_psnr", "worst_psnr", "median_ssim",
                            "worst_ssim", "median_hole_fraction", "worst_hole_fraction", "speedup"})
      EXPECT_TRUE(entry.contains(key)) << settings[s] << " " << key;
  }
  EXPECT_TRUE(summary["settings"][0]["median_psnr"].is_null()) << "exact: +inf as null";
  EXPECT_EQ(summary["settings"][0]["median_rmse"], 0.0);
  EXPECT_EQ(summary["settings"][0]["worst_ssim"], 1.0);
  EXPECT_FALSE(summary["pareto_front"].empty());

  const std::string svg = test::readFile(eval.out / "error_vs_time.svg");
  ASSERT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_EQ(count(svg, "<circle class=\"marker\""), settings.size());
  for (const std::string& name : settings) EXPECT_NE(svg.find(">" + name + "</text>"), std::string::npos) << name;

  const nlohmann::json& sheetRows = summary["contact_sheet"]["rows"];
  ASSERT_GE(sheetRows.size(), 1u);
  ASSERT_LE(sheetRows.size(), 3u);
  EXPECT_NE(std::find(sheetRows.begin(), sheetRows.end(), "overdraw=4"), sheetRows.end());
  const auto [w, h] = pngSize(eval.out / "contact_sheet.png");
  EXPECT_EQ(w, 3u * 96u);
  EXPECT_EQ(h, sheetRows.size() * 64u);
}

TEST(EvalCli, MoreSurfelsNeverLeaveMoreHolesOnAStaticView) {
  const EvalRun eval;
  const test::CommandResult run = eval.run("--size 160x120 --frames 1 --sweep overdraw=0.5,1,2,4,8 --quiet");
  ASSERT_EQ(run.status, 0) << run.err;
  const std::vector<test::CsvRow> rows = eval.rows();
  ASSERT_EQ(rows.size(), 6u);  // exact and five overdraws
  for (std::size_t i = 2; i < rows.size(); ++i) {
    EXPECT_GE(rows[i].number("surfels"), rows[i - 1].number("surfels")) << rows[i].fields.at("setting");
    EXPECT_LE(rows[i].number("hole_fraction"), rows[i - 1].number("hole_fraction")) << rows[i].fields.at("setting");
  }
  EXPECT_GT(rows[1].number("hole_fraction"), rows[5].number("hole_fraction"))
      << "a sparse prefix must leave holes that a dense one fills";
}

TEST(EvalCli, OtherOrderingsAreMadeOnDemand) {
  const EvalRun eval;
  const test::CommandResult run = eval.run("--size 64x48 --frames 1 --sweep ordering=farthest,random,dart --capture-from triangles --quiet");
  ASSERT_EQ(run.status, 0) << run.err;
  const std::vector<test::CsvRow> rows = eval.rows();
  ASSERT_EQ(rows.size(), 4u);
  for (std::size_t i = 1; i < rows.size(); ++i) EXPECT_GT(rows[i].number("surfels"), 0.0) << i;
  EXPECT_EQ(rows[2].fields.at("setting"), "ordering=random");
}

TEST(EvalCli, BadSweepsFailWithUsageErrors) {
  const EvalRun eval;
  const test::CommandResult unknown = eval.run("--sweep colour=1");
  EXPECT_EQ(unknown.status, 2);
  EXPECT_NE(unknown.err.find("unknown key 'colour'"), std::string::npos) << unknown.err;
  EXPECT_EQ(eval.run("--sweep overdraw=").status, 2);
  EXPECT_EQ(eval.run("--sweep overdraw=1,x").status, 2);
  EXPECT_EQ(eval.run("--sweep ordering=best").status, 2);
  EXPECT_EQ(eval.run("--size 10").status, 2);
  EXPECT_FALSE(std::filesystem::exists(eval.out / "eval.csv"));
}

// The baseline options (--point-size …) apply to every setting; "KEY=V+KEY=V" changes several at once:
// "point=0.5+overdraw=4" is the baseline itself, and a tiny threshold descends to geometry everywhere.
TEST(EvalCli, BaselineOptionsAndCombinedSettings) {
  const EvalRun eval;
  const test::CommandResult run = eval.run("--size 96x64 --frames 2 --point-size 0.5 --sweep overdraw=4 "
                                           "--sweep point=0.5+overdraw=4 --sweep point=2+threshold=0.001 --quiet");
  ASSERT_EQ(run.status, 0) << run.err;
  const std::vector<test::CsvRow> rows = eval.rows();
  ASSERT_EQ(rows.size(), 8u);  // exact and three settings, two frames each
  for (std::size_t frame = 0; frame < 2; ++frame) {
    const test::CsvRow& baseline = rows[2 + frame];
    const test::CsvRow& same = rows[4 + frame];
    const test::CsvRow& geometry = rows[6 + frame];
    EXPECT_EQ(same.fields.at("setting"), "point=0.5+overdraw=4");
    EXPECT_GT(baseline.number("surfels"), 0.0);
    EXPECT_EQ(same.number("surfels"), baseline.number("surfels"));
    EXPECT_EQ(same.fields.at("rmse"), baseline.fields.at("rmse"));
    EXPECT_EQ(geometry.number("surfels"), 0.0) << "every node above the threshold: all geometry";
    EXPECT_EQ(geometry.number("rmse"), 0.0);
  }
  EXPECT_EQ(eval.run("--sweep point=1,2+threshold=3").status, 2) << "one value per key when combined";
  EXPECT_EQ(eval.run("--sweep point=1+").status, 2);
  EXPECT_EQ(eval.run("--sweep point=1+size=3").status, 2);
}

TEST(EvalCli, SimplifiedMeshesAreMeasuredLikeSurfels) {
  const EvalRun eval;
  const test::CommandResult run = eval.run("--size 96x64 --frames 2 --sweep simplify=0.5 --sweep overdraw=4 --quiet");
  ASSERT_EQ(run.status, 0) << run.err;
  const std::vector<test::CsvRow> rows = eval.rows();
  ASSERT_EQ(rows.size(), 6u);  // exact, simplify=0.5, overdraw=4; two frames each
  for (std::size_t i = 2; i < 4; ++i) {
    EXPECT_EQ(rows[i].fields.at("setting"), "simplify=0.5");
    EXPECT_EQ(rows[i].number("surfels"), 0.0) << "triangles in place of surfels";
    EXPECT_GT(rows[i].number("triangles"), 0.0);
    EXPECT_LT(rows[i].number("triangles"), rows[i - 2].number("triangles")) << "fewer than exact, same view";
    EXPECT_TRUE(std::isfinite(rows[i].number("rmse")));
    EXPECT_TRUE(std::isfinite(rows[i].number("ssim")));
  }

  const nlohmann::json summary = nlohmann::json::parse(test::readFile(eval.out / "summary.json"));
  EXPECT_EQ(summary["baseline"], "overdraw=4") << "simplified meshes are never the surfel baseline";
  ASSERT_EQ(summary["simplification"].size(), 1u);
  const nlohmann::json& made = summary["simplification"][0];
  EXPECT_EQ(made["ratio"], 0.5);
  EXPECT_GE(made["seconds"].get<double>(), 0.0);
  EXPECT_LT(made["mesh_triangles_after"].get<double>(), made["mesh_triangles_before"].get<double>());
  EXPECT_LE(made["kept_fraction"].get<double>(), 0.5 + 1e-3);

  const std::string svg = test::readFile(eval.out / "error_vs_time.svg");
  EXPECT_EQ(count(svg, "<circle class=\"marker\""), 3u);
  EXPECT_NE(svg.find("simplified meshes"), std::string::npos) << "its own legend entry";
}

TEST(EvalCli, SimplifyRatiosOutsideZeroToOneAreUsageErrors) {
  const EvalRun eval;
  for (const char* bad : {"simplify=0", "simplify=1.5", "simplify=x"}) {
    const test::CommandResult run = eval.run(std::string("--sweep ") + bad);
    EXPECT_EQ(run.status, 2) << bad;
    EXPECT_NE(run.err.find("simplify"), std::string::npos) << run.err;
  }
}

}  // namespace
}  // namespace pbs
