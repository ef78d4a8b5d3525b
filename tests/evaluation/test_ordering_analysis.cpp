// The measuring of `pbs analyze`, called in process: a captured root's orderings ranked by how evenly
// their prefixes spread, and ρ(k) measured right on known layouts read from a .surfels file.
#include "test_fixtures.hpp"
#include "test_support.hpp"

#include <pbs/evaluation/ordering_analysis.hpp>
#include <pbs/scene/hierarchy.hpp>
#include <pbs/surfels/surfel_file.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace pbs {
namespace {

using test::ScratchDir;

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

// A captured root ordered every way: the exact greedy order spreads best, the paper's darts next,
// random worst.
TEST(OrderingAnalysis, CapturedRootOrderingsRankFarthestDartRandom) {
  const Scene scene = test::twoIdenticalGroups();
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  CaptureOptions capture;
  capture.resolution = 128;
  const AnalyzedOrderings analyzed = analyzeRoot(scene, hierarchy, scene.roots[0], capture, 2000, 1);
  const nlohmann::json& report = analyzed.report;
  EXPECT_EQ(report["mode"], "scene");
  EXPECT_GT(report["root"]["candidates"].get<std::uint64_t>(), 2000u);
  ASSERT_TRUE(report.contains("nodes"));
  ASSERT_EQ(report["nodes"].size(), 3u);
  std::map<std::string, nlohmann::json> byOrdering;
  for (const auto& node : report["nodes"]) {
    for (const char* key : {"path", "count", "area", "coverage", "rho_min", "rho_mean"})
      ASSERT_TRUE(node.contains(key)) << key;
    EXPECT_EQ(node["path"], "/0");
    EXPECT_LE(node["count"].get<std::uint64_t>(), 2000u);
    EXPECT_GT(node["count"].get<std::uint64_t>(), 100u);
    EXPECT_GT(node["area"].get<double>(), 0.0);
    EXPECT_GT(node["coverage"].get<double>(), 0.0);
    EXPECT_LE(node["coverage"].get<double>(), 1.0);
    EXPECT_GT(node["rho_mean"].get<double>(), 0.0);
    EXPECT_LT(node["rho_mean"].get<double>(), 1.2);
    EXPECT_GE(node["rho_min"].get<double>(), 0.0);
    EXPECT_LT(node["rho_min"].get<double>(), 1.2);
    byOrdering[node["ordering"].get<std::string>()] = node;
  }
  ASSERT_EQ(byOrdering.size(), 3u);
  EXPECT_EQ(byOrdering["farthest"]["count"], 2000u);
  const double farthest = byOrdering["farthest"]["rho_min"], dart = byOrdering["dart"]["rho_min"],
               random = byOrdering["random"]["rho_min"];
  EXPECT_GT(farthest, dart);
  EXPECT_GT(dart, random);
  EXPECT_GT(dart, 0.2);
  EXPECT_LT(random, 0.2);
}

// A hexagonal lattice of rows × cols points at spacing d in raster order, on z = 0.
SurfelArray hexLattice(int rows, int cols, double d) {
  SurfelArray array;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const glm::dvec3 p{(c + (r % 2 ? 0.5 : 0.0)) * d, r * d * std::sqrt(3.0) / 2.0, 0.0};
      array.box.extend(p);
      array.surfels.push_back({glm::vec3(p), glm::vec3(0, 0, 1), glm::u8vec4(255)});
    }
  const glm::dvec3 centre = array.box.center();
  for (Surfel& s : array.surfels) s.position -= glm::vec3(centre);
  // Each point of a hexagonal packing owns (√3/2)·d² of the surface: ρ = 1 for the whole set.
  array.area = double(array.surfels.size()) * std::sqrt(3.0) / 2.0 * d * d;
  array.coverage = 0.5;
  return array;
}

TEST(OrderingAnalysis, SurfelFileArraysMeasuredOnceAndEveryNodeListed) {
  ScratchDir dir;
  SurfelFile file;
  file.options.ordering = SurfelOrdering::Dart;
  file.options.seed = 7;
  file.arrays.push_back(hexLattice(30, 30, 0.1));  // 900 points in raster order
  file.arrays.push_back(hexLattice(10, 10, 2.0));  // 100 points
  file.nodes = {{"/0", 0}, {"/0/1", 1}, {"/1", 0}};
  const auto path = dir / "lattice.surfels";
  writeSurfelFile(path, file);

  SurfelFileReader reader(path);
  const AnalyzedOrderings analyzed = analyzeSurfelFile(reader);
  const nlohmann::json& report = analyzed.report;
  ASSERT_EQ(report["nodes"].size(), 3u);
  ASSERT_EQ(report["arrays"].size(), 2u);
  EXPECT_EQ(report["ordering"], "dart");
  const auto& a0 = report["nodes"][0];
  const auto& a1 = report["nodes"][1];
  const auto& shared = report["nodes"][2];
  EXPECT_EQ(a0["path"], "/0");
  EXPECT_EQ(a1["path"], "/0/1");
  EXPECT_EQ(shared["path"], "/1");
  EXPECT_EQ(a0["array"], 0);
  EXPECT_EQ(shared["array"], 0);
  for (const char* key : {"count", "area", "coverage", "rho_min", "rho_mean"}) EXPECT_EQ(a0[key], shared[key]) << key;
  EXPECT_EQ(report["arrays"][0]["nodes"], nlohmann::json({"/0", "/1"}));

  // Raster order: d_min(k) = d for every k, so ρ(k) = sqrt(k / N), worst at k = 100 and 1 at k = N.
  EXPECT_EQ(a0["count"], 900u);
  EXPECT_NEAR(a0["area"].get<double>(), 900 * std::sqrt(3.0) / 2.0 * 0.01, 1e-9);
  EXPECT_NEAR(a0["coverage"].get<double>(), 0.5, 1e-12);
  EXPECT_NEAR(a0["rho_min"].get<double>(), std::sqrt(100.0 / 900.0), 1e-3);
  EXPECT_NEAR(a0["d_min"].get<double>(), 0.1, 1e-4);
  double mean = 0.0;  // the 32 log-spaced k of summarizeBlueNoise, from 100 to 900
  for (int i = 0; i < 32; ++i) mean += std::sqrt(std::round(100.0 * std::pow(9.0, i / 31.0)) / 900.0) / 32.0;
  EXPECT_NEAR(a0["rho_mean"].get<double>(), mean, 2e-3);
  // A 100-point array: the only k ≥ 100 is the whole lattice.
  EXPECT_EQ(a1["count"], 100u);
  EXPECT_NEAR(a1["rho_min"].get<double>(), 1.0, 1e-3);
  EXPECT_NEAR(a1["rho_mean"].get<double>(), 1.0, 1e-3);

  const auto csv = lines(prefixCsv(analyzed.measured));
  ASSERT_EQ(csv.size(), 1u + 900u + 100u);  // each array once
  EXPECT_EQ(csv[900].rfind("dart,/0,0,900,", 0), 0u) << csv[900];
  // ρ(900) = 1 on the full hexagonal lattice.
  const std::string last = csv[900];
  std::vector<std::string> fields;
  std::stringstream ss(last);
  for (std::string f; std::getline(ss, f, ',');) fields.push_back(f);
  ASSERT_GE(fields.size(), 6u);
  EXPECT_NEAR(std::stod(fields[5]), 1.0, 1e-3);
  // ρ(k) drawn for every k up to 200, then about 1 % apart.
  const PlotSeries series = rhoSeries(analyzed.measured[0], "lattice");
  EXPECT_EQ(series.points.front().first, 2.0);
  EXPECT_EQ(series.points.back().first, 900.0);
  EXPECT_LT(series.points.size(), 900u);
}

}  // namespace
}  // namespace pbs
