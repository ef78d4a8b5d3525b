// The evaluation library, called in process as a program embedding pbs would: settings parsed from
// sweep texts (and refused with the option they came from), the peers converging to the reference,
// frame kinds along the approach, fewer holes with more surfels, arrays of other orderings and simplified
// meshes made on demand, and the outputs (CSV rows, summary, Pareto front) built from the results.
#include "surfeled_scene.hpp"
#include "test_support.hpp"

#include <pbs/evaluation/eval_outputs.hpp>
#include <pbs/evaluation/eval_run.hpp>
#include <pbs/evaluation/eval_settings.hpp>
#include <pbs/evaluation/eval_sources.hpp>
#include <pbs/surfels/surfel_cache.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace pbs {
namespace {

// The two-groups scene, its surfels written to a file, and the evaluation's sources over that file.
class Evaluation {
 public:
  Evaluation()
      : surfeled_(test::writtenSurfeledScene(scratch_ / "groups.surfels")),
        reader_(scratch_ / "groups.surfels"),
        hierarchy_(hierarchyWithSurfels(surfeled_.scene, *reader_)),
        sources_(surfeled_.scene, hierarchy_, std::move(*reader_), 64u << 20, CaptureSource::Triangles),
        simplified_(surfeled_.scene) {}

  std::vector<Camera> approach(std::uint32_t frames) const { return test::approachCameras(surfeled_, frames); }

  // Runs `settings` (peers, then sweeps over `baseline`) on `cameras` against Embree at 4 samples per pixel.
  EvalResults run(const std::vector<EvalSetting>& settings, const std::vector<Camera>& cameras,
                  const LodOptions& baseline = {}, int draws = 1) {
    EvalInputs inputs;
    inputs.referenceSamples = 4;
    inputs.draws = draws;
    inputs.kindSurfels = &sources_.decisions();
    inputs.kindLod = baseline;
    return runEval(
        surfeled_.scene, hierarchy_, cameras, settings, inputs, [&](const EvalSetting& s) { return sources_.of(s); },
        [&](const EvalSetting& s) -> const Scene& { return simplified_.of(s); },
        [](std::size_t, std::size_t, const std::string&) {});
  }

  const EvalSimplifiedScenes& simplified() const { return simplified_; }

 private:
  test::ScratchDir scratch_;
  test::SurfeledScene surfeled_;
  std::optional<SurfelFileReader> reader_;
  Hierarchy hierarchy_;
  EvalSurfelSources sources_;
  EvalSimplifiedScenes simplified_;
};

// Groups drawn as surfels need `grow`: arrays of 4000 surfels are too short for a group that fills a good
// part of even a 160-pixel view, and would be descended into.
LodOptions grown() {
  LodOptions lod;
  lod.descendExhausted = false;
  return lod;
}

std::size_t indexOf(const std::vector<EvalSetting>& settings, const std::string& name) {
  const auto found =
      std::find_if(settings.begin(), settings.end(), [&](const EvalSetting& s) { return s.name == name; });
  EXPECT_NE(found, settings.end()) << name;
  return std::size_t(found - settings.begin());
}

TEST(EvalSettings, PeersThenTheBaselineThenSweepsAndDuplicatesDropped) {
  const std::vector<EvalSetting> settings =
      evalSettings({"embree=1,4", "exact"}, {"overdraw=16", "overdraw=2,8", "point=1+threshold=64"}, LodOptions{});
  std::vector<std::string> names;
  for (const EvalSetting& s : settings) names.push_back(s.name);
  // overdraw=16 draws like the baseline (16 is the default), so it is measured once, as "surfels".
  EXPECT_EQ(names, (std::vector<std::string>{"embree=1", "embree=4", "exact=1", "surfels", "overdraw=2", "overdraw=8",
                                             "point=1+threshold=64"}));
  EXPECT_EQ(baselineSetting(settings), 3u);
  EXPECT_TRUE(settings[1].isPeer());
  EXPECT_EQ(settings[1].samples, 4u);
  EXPECT_EQ(settings[4].lod.overdraw, 2.0);
  EXPECT_EQ(settings[6].lod.pointSize, 1.0f);
  EXPECT_EQ(settings[6].lod.threshold, 64.0);
  const std::vector<EvalSetting> rays = evalSettings({}, {"rays=keep,descend"}, LodOptions{});
  ASSERT_EQ(rays.size(), 2u) << "the baseline (rays=keep, the library's default) and the other";
  EXPECT_FALSE(rays[0].lod.descendWhereRaysCheaper);
  EXPECT_TRUE(rays[1].lod.descendWhereRaysCheaper);
  EXPECT_EQ(rays[1].name, "rays=descend");
  LodOptions preferring;
  preferring.raysPreference = 2.0;
  const std::vector<EvalSetting> preference = evalSettings({}, {"rays-preference=1,3"}, preferring);
  ASSERT_EQ(preference.size(), 3u) << "the baseline, then each value";
  EXPECT_EQ(preference[1].lod.raysPreference, 1.0);
  EXPECT_EQ(preference[2].lod.raysPreference, 3.0);
}

TEST(EvalSettings, BadTextsAreRefusedNamingTheirOption) {
  const auto refusal = [](const std::vector<std::string>& peers, const std::vector<std::string>& sweeps) {
    try {
      evalSettings(peers, sweeps, LodOptions{});
    } catch (const SweepError& error) {
      return error.option() + ": " + error.what();
    }
    return std::string("accepted");
  };
  EXPECT_EQ(refusal({}, {"colour=1"}).rfind("--sweep: unknown key 'colour'", 0), 0u) << refusal({}, {"colour=1"});
  EXPECT_EQ(refusal({"overdraw=2"}, {}).rfind("--peers:", 0), 0u) << "peers are exact renderers";
  for (const char* bad : {"overdraw=", "overdraw=1,x", "ordering=best", "embree=3", "point=1,2+threshold=3", "point=1+",
                          "simplify=0", "simplify=1.5", "exhausted=sometimes", "rays=sometimes", "rays-preference=0"})
    EXPECT_EQ(refusal({}, {bad}).rfind("--sweep:", 0), 0u) << bad;
}

// More samples converge to the reference; the speed-up is over the faster 1-sample peer on each frame;
// the approach goes from far (surfels) to near (geometry).
TEST(EvalRun, PeersConvergeAndTheApproachGoesFromFarToNear) {
  Evaluation evaluation;
  const std::vector<EvalSetting> settings = evalSettings({"embree=1,4", "exact=1"}, {}, grown());
  const std::vector<Camera> cameras = evaluation.approach(4);
  const EvalResults results = evaluation.run(settings, cameras, grown());
  ASSERT_EQ(results.views.size(), 4u);
  ASSERT_EQ(results.settings.size(), settings.size());
  EXPECT_EQ(results.views.front().kind, FrameKind::Far);
  EXPECT_EQ(results.views.back().kind, FrameKind::Near);
  EXPECT_GE(results.views.back().geometryShare, 0.5);

  const EvalSettingResult& rays1 = results.settings[indexOf(settings, "embree=1")];
  const EvalSettingResult& rays4 = results.settings[indexOf(settings, "embree=4")];
  const EvalSettingResult& raster1 = results.settings[indexOf(settings, "exact=1")];
  const EvalSettingResult& surfels = results.settings[indexOf(settings, "surfels")];
  for (std::size_t f = 0; f < cameras.size(); ++f) {
    EXPECT_LT(rays4.frames[f].error.flipForegroundMean, rays1.frames[f].error.flipForegroundMean) << f;
    EXPECT_GT(rays1.frames[f].error.flipForegroundMean, 0.0) << f;
    EXPECT_EQ(std::max(rays1.frames[f].speedupOverFastestExact, raster1.frames[f].speedupOverFastestExact), 1.0) << f;
    EXPECT_GT(surfels.frames[f].speedupOverFastestExact, 0.0) << f;
  }
  EXPECT_GT(surfels.frames.front().stats.surfels, 0u) << "the far frame draws surfels";
  EXPECT_GT(surfels.frames.back().stats.triangles, 0u) << "the near frame draws geometry";

  // The outputs built from these results: one CSV row per setting and frame, a summary per kind.
  const std::string csv = evalCsv(settings, results);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), std::ptrdiff_t(1 + settings.size() * cameras.size()));
  EXPECT_EQ(csv.rfind(kEvalCsvHeader, 0), 0u);
  const EvalSummary all = summarize("surfels", surfels, results.views);
  const EvalSummary far = summarize("surfels", surfels, results.views, FrameKind::Far);
  EXPECT_EQ(all.frames, 4u);
  EXPECT_GE(far.frames, 1u);
  EXPECT_LT(far.frames, 4u);
  EXPECT_GE(all.worstFlip, all.medianFlip);
  EvalRunInfo info;
  info.path = "approach";
  info.frames = 4;
  info.baseline = baselineSetting(settings);
  const nlohmann::json summary = evalSummaryJson(info, settings, results);
  EXPECT_EQ(summary["baseline"], "surfels");
  EXPECT_EQ(summary["settings"].size(), settings.size());
  EXPECT_TRUE(summary["settings"][indexOf(settings, "surfels")].contains("near"));

  // All files at once: the contact sheet holds the baseline and one ray per pixel, three tiles a row.
  info.width = cameras[0].width;
  info.height = cameras[0].height;
  const EvalFiles files = evalFiles(info, settings, results, 2, glm::vec3(1.0f));
  EXPECT_EQ(files.csv, csv);
  EXPECT_EQ(files.summaries.size(), settings.size());
  const nlohmann::json& rows = files.summary["contact_sheet"]["rows"];
  EXPECT_NE(std::find(rows.begin(), rows.end(), "surfels"), rows.end());
  EXPECT_NE(std::find(rows.begin(), rows.end(), "embree=1"), rows.end());
  EXPECT_EQ(files.sheetWidth, 3 * info.width);
  EXPECT_EQ(files.sheetHeight, rows.size() * info.height);
  EXPECT_EQ(files.sheet.size(), std::size_t(files.sheetWidth) * files.sheetHeight * 3);
  EXPECT_EQ(files.plot.rfind("<svg", 0), 0u);
}

// With points of a fixed size (prefix-sized discs close a sparse prefix by growing instead).
TEST(EvalRun, MoreSurfelsNeverLeaveMoreHolesOnAStaticView) {
  Evaluation evaluation;
  LodOptions baseline = grown();
  baseline.splat = SplatMode::Nearest;
  baseline.pointSize = 2.0f;
  baseline.overdraw = 4.0;
  const std::vector<EvalSetting> settings = evalSettings({"embree=1"}, {"overdraw=0.5,1,2,8"}, baseline);
  const EvalResults results = evaluation.run(settings, {evaluation.approach(4).front()}, baseline);
  std::vector<std::pair<double, const EvalFrame*>> byOverdraw;
  for (std::size_t s = 0; s < settings.size(); ++s)
    if (!settings[s].isPeer()) byOverdraw.emplace_back(settings[s].lod.overdraw, &results.settings[s].frames[0]);
  ASSERT_EQ(byOverdraw.size(), 5u);
  std::sort(byOverdraw.begin(), byOverdraw.end());
  for (std::size_t i = 1; i < byOverdraw.size(); ++i) {
    EXPECT_GE(byOverdraw[i].second->stats.surfels, byOverdraw[i - 1].second->stats.surfels) << i;
    EXPECT_LE(byOverdraw[i].second->error.holeFraction, byOverdraw[i - 1].second->error.holeFraction) << i;
  }
  EXPECT_GT(byOverdraw.front().second->error.holeFraction, byOverdraw.back().second->error.holeFraction)
      << "a sparse prefix must leave holes that a dense one fills";
}

// Arrays of another ordering are made from the scene with the file's options; simplified meshes draw
// triangles in place of surfels: fewer than the exact renderer's from afar, and near (every node
// descended into, drawn from its own mesh) the same.
TEST(EvalRun, OtherOrderingsAndSimplifiedMeshesAreMadeOnDemand) {
  Evaluation evaluation;
  const std::vector<EvalSetting> settings =
      evalSettings({"exact=1"}, {"ordering=random,dart", "simplify=0.5"}, grown());
  const std::vector<Camera> cameras = evaluation.approach(4);
  const EvalResults results = evaluation.run(settings, {cameras[0], cameras[3]}, grown());
  for (const char* name : {"surfels", "ordering=random", "ordering=dart"})
    EXPECT_GT(results.settings[indexOf(settings, name)].frames[0].stats.surfels, 0u) << name;
  const EvalSettingResult& exact = results.settings[indexOf(settings, "exact=1")];
  const EvalSettingResult& simplified = results.settings[indexOf(settings, "simplify=0.5")];
  for (std::size_t f = 0; f < 2; ++f) {
    EXPECT_EQ(simplified.frames[f].stats.surfels, 0u) << f;
    EXPECT_GT(simplified.frames[f].stats.triangles, 0u) << f;
  }
  EXPECT_LT(simplified.frames[0].stats.triangles, exact.frames[0].stats.triangles);
  EXPECT_EQ(simplified.frames[1].stats.triangles, exact.frames[1].stats.triangles);
  const nlohmann::json made = evaluation.simplified().json();
  ASSERT_EQ(made.size(), 1u);
  EXPECT_EQ(made[0]["ratio"], 0.5);
  EXPECT_LT(made[0]["mesh_triangles_after"].get<double>(), made[0]["mesh_triangles_before"].get<double>());
}

// A setting whose threshold descends to geometry everywhere draws the exact rasterizer's picture.
TEST(EvalRun, AllGeometryDrawsTheExactRasterizersPicture) {
  Evaluation evaluation;
  const std::vector<EvalSetting> settings = evalSettings({"exact=1"}, {"threshold=0.001+geometry=raster"}, grown());
  const EvalResults results = evaluation.run(settings, evaluation.approach(2), grown());
  const EvalSettingResult& exact = results.settings[indexOf(settings, "exact=1")];
  const EvalSettingResult& geometry = results.settings[indexOf(settings, "threshold=0.001+geometry=raster")];
  for (std::size_t f = 0; f < 2; ++f) {
    EXPECT_EQ(geometry.frames[f].stats.surfels, 0u);
    EXPECT_EQ(geometry.frames[f].error.flipForegroundMean, exact.frames[f].error.flipForegroundMean) << f;
  }
}

// Timed over three draws of each view, a frame keeps the first draw's image and its reading of the file:
// the same errors and counts as one draw, the prefixes' reading charged where they were read.
TEST(EvalRun, MoreDrawsTimeTheSameFrames) {
  const std::vector<EvalSetting> settings = evalSettings({"embree=1"}, {}, grown());
  Evaluation once, thrice;
  const EvalResults one = once.run(settings, once.approach(3), grown(), 1);
  const EvalResults three = thrice.run(settings, thrice.approach(3), grown(), 3);
  double loadOnce = 0.0, loadThrice = 0.0;
  for (std::size_t s = 0; s < settings.size(); ++s)
    for (std::size_t f = 0; f < 3; ++f) {
      const EvalFrame &a = one.settings[s].frames[f], &b = three.settings[s].frames[f];
      EXPECT_EQ(a.error.flipForegroundMean, b.error.flipForegroundMean) << settings[s].name << " frame " << f;
      EXPECT_EQ(a.error.holeFraction, b.error.holeFraction);
      EXPECT_EQ(a.stats.surfels, b.stats.surfels);
      EXPECT_EQ(a.stats.triangles, b.stats.triangles);
      EXPECT_GT(b.seconds, 0.0);
      loadOnce += a.surfelLoadSeconds;
      loadThrice += b.surfelLoadSeconds;
    }
  EXPECT_GT(three.settings[indexOf(settings, "surfels")].frames[0].stats.surfels, 0u);
  EXPECT_GT(loadOnce, 0.0);
  EXPECT_GT(loadThrice, 0.0);
}

TEST(EvalOutputs, TheParetoFrontKeepsWhatNothingBeatsInBothTimeAndError) {
  // (time, error): the second is beaten by the first in both; the last ties the third's error, slower.
  const std::vector<std::pair<double, double>> points = {{1.0, 0.5}, {2.0, 0.6}, {3.0, 0.1}, {0.5, 0.9}, {4.0, 0.1}};
  EXPECT_EQ(paretoFront(points), (std::vector<std::size_t>{3, 0, 2}));
}

}  // namespace
}  // namespace pbs
