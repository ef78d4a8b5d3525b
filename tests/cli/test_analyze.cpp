// `pbs analyze` and the flat-patch spectrum: white noise is flat, farthest-point order is blue, ρ(k) is
// measured right on known layouts, and the command's files are whole and well formed.
#include "test_support.hpp"

#include <pbs/surfels/ordering.hpp>
#include <pbs/surfels/point_spectrum.hpp>
#include <pbs/surfels/surfel_file.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

namespace pbs {
namespace {

using test::runPbs;
using test::ScratchDir;

PointOrdering byName(SurfelOrdering ordering) {
  return [ordering](std::span<const glm::vec3> points, std::uint32_t max, std::uint64_t seed) {
    return orderPoints(ordering, points, max, seed);
  };
}

TEST(Periodogram, LatticeHasPowerOnlyAtItsReciprocalLattice) {
  constexpr int m = 8;
  std::vector<glm::vec2> points;
  for (int y = 0; y < m; ++y)
    for (int x = 0; x < m; ++x) points.emplace_back((x + 0.5f) / m, (y + 0.5f) / m);
  constexpr std::uint32_t F = 20;
  const std::vector<double> p = periodogram(points, F);
  ASSERT_EQ(p.size(), (2 * F + 1) * (2 * F + 1));
  for (int fy = -int(F); fy <= int(F); ++fy) {
    for (int fx = -int(F); fx <= int(F); ++fx) {
      const double expected = (fx % m == 0 && fy % m == 0) ? double(m * m) : 0.0;
      EXPECT_NEAR(p[std::size_t(fy + int(F)) * (2 * F + 1) + std::size_t(fx + int(F))], expected, 1e-6)
          << fx << "," << fy;
    }
  }
  // A single point has power 1 everywhere.
  const glm::vec2 one[] = {{0.3f, 0.7f}};
  for (double v : periodogram(one, 5)) EXPECT_NEAR(v, 1.0, 1e-12);
}

TEST(FlatSpectrum, RandomIsFlatAndFarthestIsBlue) {
  FlatSpectrumOptions options;
  options.candidates = 20000;
  options.count = 256;
  options.realizations = 8;
  const FlatSpectrum random = flatPatchSpectrum(byName(SurfelOrdering::Random), options);
  const FlatSpectrum farthest = flatPatchSpectrum(byName(SurfelOrdering::Farthest), options);
  const FlatSpectrum dart = flatPatchSpectrum(byName(SurfelOrdering::Dart), options);
  ASSERT_EQ(random.maxFrequency, 64u);  // 4·sqrt(256)
  ASSERT_EQ(random.radial.power.size(), 64u);
  EXPECT_NEAR(random.count, 256.0, 20.0);  // the points inside the measured window, on average

  // White noise: expected power 1 at every f ≠ 0; the annuli from r = 4 average ≥ ~100 values.
  double sum = 0.0;
  for (std::size_t i = 0; i < random.radial.power.size(); ++i) {
    if (random.radial.frequency[i] >= 4) {
      EXPECT_NEAR(random.radial.power[i], 1.0, 0.45) << "r " << i + 1;
    }
    sum += random.radial.power[i];
  }
  EXPECT_NEAR(sum / double(random.radial.power.size()), 1.0, 0.08);
  EXPECT_NEAR(random.lowFrequencyPower, 1.0, 0.35);

  // Blue noise: little power below the mean spacing's frequency (sqrt(n) = 16), ≈ 1 far above it.
  EXPECT_LT(farthest.lowFrequencyPower, 0.25);
  EXPECT_LT(dart.lowFrequencyPower, 0.5);
  for (std::size_t r = 1; r <= 8; ++r) EXPECT_LT(farthest.radial.power[r - 1], 0.5) << "r " << r;
  double high = 0.0;
  for (std::size_t r = 48; r <= 64; ++r) high += farthest.radial.power[r - 1] / 17.0;
  EXPECT_NEAR(high, 1.0, 0.25);

  for (const FlatSpectrum* s : {&random, &farthest, &dart})
    for (double a : s->radial.anisotropy) {
      EXPECT_TRUE(std::isfinite(a));
      EXPECT_LT(a, 10.0);
    }
  // Averaging 8 white-noise periodograms: variance / mean² ≈ 1/8, about -9 dB, away from the axes' bias.
  double anisotropy = 0.0;
  for (std::size_t r = 16; r <= 64; ++r) anisotropy += random.radial.anisotropy[r - 1] / 49.0;
  EXPECT_NEAR(anisotropy, -9.0, 1.5);
}

TEST(FlatSpectrum, RejectsBadOptions) {
  FlatSpectrumOptions options;
  options.candidates = 10;
  options.count = 20;
  EXPECT_THROW(flatPatchSpectrum(byName(SurfelOrdering::Random), options), std::invalid_argument);
  options.count = 0;
  EXPECT_THROW(flatPatchSpectrum(byName(SurfelOrdering::Random), options), std::invalid_argument);
}

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
  if (dir && std::filesystem::exists(*dir / "spot.glb")) return "'" + (*dir / "spot.glb").string() + "'";
  return "default";
}

TEST(AnalyzeCommand, SceneOrderingsRankFarthestDartRandom) {
  const auto result = runPbs("analyze " + smallScene() + " --max 2000 --resolution 128 --json --no-spectrum");
  const nlohmann::json report = parseJson(result);
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
  EXPECT_FALSE(report.contains("spectrum"));
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

TEST(AnalyzeCommand, SurfelFileArraysMeasuredOnceAndEveryNodeListed) {
  ScratchDir dir;
  SurfelFile file;
  file.options.ordering = SurfelOrdering::Dart;
  file.options.seed = 7;
  file.arrays.push_back(hexLattice(30, 30, 0.1));  // 900 points in raster order
  file.arrays.push_back(hexLattice(10, 10, 2.0));  // 100 points
  file.nodes = {{"/0", 0}, {"/0/1", 1}, {"/1", 0}};
  const auto path = dir / "lattice.surfels";
  writeSurfelFile(path, file);

  const auto result =
      runPbs("analyze '" + path.string() + "' --json --no-spectrum -o '" + (dir / "out").string() + "'");
  const nlohmann::json report = parseJson(result);
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

  const auto csv = lines(test::readFile(dir / "out" / "analyze.csv"));
  ASSERT_EQ(csv.size(), 1u + 900u + 100u);  // each array once
  EXPECT_EQ(csv[900].rfind("dart,/0,0,900,", 0), 0u) << csv[900];
  // ρ(900) = 1 on the full hexagonal lattice.
  const std::string last = csv[900];
  std::vector<std::string> fields;
  std::stringstream ss(last);
  for (std::string f; std::getline(ss, f, ',');) fields.push_back(f);
  ASSERT_GE(fields.size(), 6u);
  EXPECT_NEAR(std::stod(fields[5]), 1.0, 1e-3);
  const std::string svg = test::readFile(dir / "out" / "rho.svg");
  EXPECT_EQ(occurrences(svg, "<polyline"), 2u);
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
