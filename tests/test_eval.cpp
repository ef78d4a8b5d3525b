// `pbs eval`: the files it writes (CSV columns, one row per setting and frame, summary keys, one
// marker per setting, the contact sheet's size), zero error for exact against exact, and fewer holes
// with more surfels on a static view.
#include "test_fixtures.hpp"
#include "cli_scenes.hpp"
#include "test_support.hpp"

#include <pbs/scene/gltf_export.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace pbs {
namespace {

using test::groupsWithSurfels;
using test::ScratchDir;

constexpr const char* kHeader =
    "setting,frame,azimuth,seconds,traverse_seconds,raster_seconds,triangles,surfels,rmse,psnr,ssim,hole_fraction";

struct CsvRow {
  std::map<std::string, std::string> fields;
  double number(const std::string& key) const { return std::stod(fields.at(key)); }
};

std::vector<CsvRow> readCsv(const std::filesystem::path& file, std::string& header) {
  std::istringstream in(test::readFile(file));
  std::getline(in, header);
  std::vector<std::string> columns;
  {
    std::istringstream h(header);
    for (std::string c; std::getline(h, c, ',');) columns.push_back(c);
  }
  std::vector<CsvRow> rows;
  for (std::string line; std::getline(in, line);) {
    std::istringstream l(line);
    CsvRow row;
    std::size_t i = 0;
    for (std::string value; std::getline(l, value, ','); ++i) row.fields[i < columns.size() ? columns[i] : "?"] = value;
    EXPECT_EQ(i, columns.size()) << line;
    rows.push_back(row);
  }
  return rows;
}

// Width and height from a PNG's IHDR chunk (big-endian at bytes 16 and 20).
std::pair<std::uint32_t, std::uint32_t> pngSize(const std::filesystem::path& file) {
  const std::string bytes = test::readFile(file);
  if (bytes.size() < 24 || bytes.compare(1, 3, "PNG") != 0) return {0, 0};
  const auto word = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (std::size_t i = 0; i < 4; ++i) v = (v << 8) | std::uint8_t(bytes[at + i]);
    return v;
  };
  return {word(16), word(20)};
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(EvalCli, WritesOneRowPerSettingAndFrameAndExactHasNoError) {
  ScratchDir scratch;
  const auto [scene, surfels] = groupsWithSurfels(scratch);
  const std::filesystem::path out = scratch / "eval";
  const test::CommandResult run =
      test::runPbs("eval " + scene + " --surfels " + surfels + " -o '" + out.string() +
                   "' --size 96x64 --frames 2 --sweep overdraw=1,4 --sweep point=4 --quiet");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(run.err.empty()) << "--quiet: " << run.err;

  std::string header;
  const std::vector<CsvRow> rows = readCsv(out / "eval.csv", header);
  EXPECT_EQ(header, kHeader);
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

  const nlohmann::json summary = nlohmann::json::parse(test::readFile(out / "summary.json"));
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

  const std::string svg = test::readFile(out / "error_vs_time.svg");
  ASSERT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_EQ(count(svg, "<circle class=\"marker\""), settings.size());
  for (const std::string& name : settings) EXPECT_NE(svg.find(">" + name + "</text>"), std::string::npos) << name;

  const nlohmann::json& sheetRows = summary["contact_sheet"]["rows"];
  ASSERT_GE(sheetRows.size(), 1u);
  ASSERT_LE(sheetRows.size(), 3u);
  EXPECT_NE(std::find(sheetRows.begin(), sheetRows.end(), "overdraw=4"), sheetRows.end());
  const auto [w, h] = pngSize(out / "contact_sheet.png");
  EXPECT_EQ(w, 3u * 96u);
  EXPECT_EQ(h, sheetRows.size() * 64u);
}

TEST(EvalCli, MoreSurfelsNeverLeaveMoreHolesOnAStaticView) {
  ScratchDir scratch;
  const auto [scene, surfels] = groupsWithSurfels(scratch);
  const std::filesystem::path out = scratch / "eval";
  const test::CommandResult run = test::runPbs("eval " + scene + " --surfels " + surfels + " -o '" + out.string() +
                                               "' --size 160x120 --frames 1 --sweep overdraw=0.5,1,2,4,8 --quiet");
  ASSERT_EQ(run.status, 0) << run.err;
  std::string header;
  const std::vector<CsvRow> rows = readCsv(out / "eval.csv", header);
  ASSERT_EQ(rows.size(), 6u);  // exact and five overdraws
  for (std::size_t i = 2; i < rows.size(); ++i) {
    EXPECT_GE(rows[i].number("surfels"), rows[i - 1].number("surfels")) << rows[i].fields.at("setting");
    EXPECT_LE(rows[i].number("hole_fraction"), rows[i - 1].number("hole_fraction")) << rows[i].fields.at("setting");
  }
  EXPECT_GT(rows[1].number("hole_fraction"), rows[5].number("hole_fraction"))
      << "a sparse prefix must leave holes that a dense one fills";
}

TEST(EvalCli, OtherOrderingsAreMadeOnDemand) {
  ScratchDir scratch;
  const auto [scene, surfels] = groupsWithSurfels(scratch);
  const std::filesystem::path out = scratch / "eval";
  const test::CommandResult run =
      test::runPbs("eval " + scene + " --surfels " + surfels + " -o '" + out.string() +
                   "' --size 64x48 --frames 1 --sweep ordering=farthest,random,dart --capture-from triangles --quiet");
  ASSERT_EQ(run.status, 0) << run.err;
  std::string header;
  const std::vector<CsvRow> rows = readCsv(out / "eval.csv", header);
  ASSERT_EQ(rows.size(), 4u);
  for (std::size_t i = 1; i < rows.size(); ++i) EXPECT_GT(rows[i].number("surfels"), 0.0) << i;
  EXPECT_EQ(rows[2].fields.at("setting"), "ordering=random");
}

TEST(EvalCli, BadSweepsFailWithUsageErrors) {
  ScratchDir scratch;
  const auto [scene, surfels] = groupsWithSurfels(scratch);
  const std::string common = "eval " + scene + " --surfels " + surfels + " -o '" + (scratch / "e").string() + "' ";
  const test::CommandResult unknown = test::runPbs(common + "--sweep colour=1");
  EXPECT_EQ(unknown.status, 2);
  EXPECT_NE(unknown.err.find("unknown key 'colour'"), std::string::npos) << unknown.err;
  EXPECT_EQ(test::runPbs(common + "--sweep overdraw=").status, 2);
  EXPECT_EQ(test::runPbs(common + "--sweep overdraw=1,x").status, 2);
  EXPECT_EQ(test::runPbs(common + "--sweep ordering=best").status, 2);
  EXPECT_EQ(test::runPbs(common + "--size 10").status, 2);
  EXPECT_FALSE(std::filesystem::exists(scratch / "e" / "eval.csv"));
}

}  // namespace
}  // namespace pbs
