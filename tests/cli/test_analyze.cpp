// `pbs analyze`: the command's files are whole and well formed, and bad inputs give one error line. What
// it measures is tested on the library (tests/evaluation/test_ordering_analysis.cpp).
#include "test_support.hpp"

#include <pbs/surfels/surfel_file.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

namespace pbs {
namespace {

using test::runPbs;
using test::ScratchDir;

nlohmann::json parseJson(const test::CommandResult& result) {
  EXPECT_EQ(result.status, 0) << result.err;
  try {
    return nlohmann::json::parse(result.out);
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not JSON: " << e.what() << "\n" << result.out;
    return {};
  }
}

// A small shared scene keeps the suite fast (capturing the 19M-triangle default scene takes seconds
// at any resolution); without the shared scenes the default scene is used.
std::string smallScene() {
  const auto dir = test::sharedScenesDir();
  if (!dir || !std::filesystem::exists(*dir / "spot.glb")) return "default";
  return test::quoted(*dir / "spot.glb");
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(AnalyzeCommand, OutputFolderHoldsCsvSvgAndSpectrum) {
  ScratchDir dir;
  const auto out = dir / "out";
  const auto result = runPbs("analyze " + smallScene() +
                             " --max 300 --resolution 96 --spectrum-points 64 --spectrum-candidates 3000 "
                             "--spectrum-seeds 2 --json -o '" +
                             out.string() + "'");
  const nlohmann::json report = parseJson(result);
  ASSERT_EQ(report["nodes"].size(), 3u);
  std::size_t expectedRows = 0;
  for (const auto& node : report["nodes"]) expectedRows += node["count"].get<std::size_t>();

  const auto csv = lines(test::readFile(out / "analyze.csv"));
  ASSERT_FALSE(csv.empty());
  EXPECT_EQ(csv.front(), "ordering,path,array,k,d_min,rho,mean_nn");
  EXPECT_EQ(csv.size(), expectedRows + 1);
  EXPECT_EQ(csv[1].rfind("farthest,/0,,1,,,", 0), 0u) << csv[1];
  std::size_t meanNNRows = 0;
  for (std::size_t i = 1; i < csv.size(); ++i) {
    EXPECT_EQ(std::count(csv[i].begin(), csv[i].end(), ','), 6) << csv[i];
    if (csv[i].back() != ',') ++meanNNRows;
  }
  EXPECT_GE(meanNNRows, 3u * 20u);  // ~32 log-spaced k per ordering
  EXPECT_LE(meanNNRows, 3u * 33u);

  const std::string svg = test::readFile(out / "rho.svg");
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_EQ(occurrences(svg, "<polyline"), 3u);
  EXPECT_EQ(occurrences(svg, "<polyline"), occurrences(svg, "</polyline>"));
  for (const char* name : {">farthest<", ">dart<", ">random<"}) EXPECT_NE(svg.find(name), std::string::npos) << name;

  const auto spectrum = lines(test::readFile(out / "spectrum.csv"));
  ASSERT_FALSE(spectrum.empty());
  EXPECT_EQ(spectrum.front(), "ordering,points,frequency,power,anisotropy_db");
  EXPECT_EQ(spectrum.size(), 1u + 3u * 32u);  // F = 4·sqrt(64) annuli per ordering
  EXPECT_EQ(test::readFile(out / "spectrum.svg").rfind("<svg", 0), 0u);
  ASSERT_TRUE(report.contains("spectrum"));
  EXPECT_LT(report["spectrum"]["orderings"]["farthest"]["low_frequency_power"].get<double>(),
            report["spectrum"]["orderings"]["random"]["low_frequency_power"].get<double>());
  for (const auto& entry : std::filesystem::directory_iterator(out))
    EXPECT_EQ(entry.path().extension() == ".tmp", false) << entry.path();
}

TEST(AnalyzeCommand, BadInputsGiveOneErrorLine) {
  ScratchDir dir;
  for (const std::string& input :
       {(dir / "missing.surfels").string(), (dir / "missing.glb").string(), (dir / "garbage.surfels").string()}) {
    if (input.ends_with("garbage.surfels")) test::writeFile(input, "PBSURFEL but not really a surfel file");
    const auto result = runPbs("analyze '" + input + "' --no-spectrum");
    EXPECT_EQ(result.status, 1) << input;
    EXPECT_EQ(result.err.rfind("error:", 0), 0u) << result.err;
    EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
    EXPECT_TRUE(result.out.empty()) << result.out;
  }
  // An output folder that cannot be made: a file stands in its way.
  test::writeFile(dir / "file", "x");
  const auto result = runPbs("analyze " + smallScene() + " --max 50 --resolution 32 --no-spectrum -o '" +
                             (dir / "file" / "sub").string() + "'");
  EXPECT_EQ(result.status, 1);
  EXPECT_EQ(result.err.rfind("error:", 0), 0u) << result.err;
}

}  // namespace
}  // namespace pbs
