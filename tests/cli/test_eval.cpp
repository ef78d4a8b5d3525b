// `pbs eval`: the files it writes (CSV columns, one row per setting and frame, summary keys per frame
// kind, one marker per setting, the contact sheet's size), reading the .surfels file and the meshes as
// frames draw them, and usage errors. What the settings measure is tested on the library
// (tests/evaluation).
#include "test_fixtures.hpp"
#include "cli_scenes.hpp"
#include "output_files.hpp"
#include "test_support.hpp"

#include <pbs/scene/gltf_export.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace pbs {
namespace {

using test::groupsWithSurfels;
using test::pngSize;
using test::readCsv;
using test::ScratchDir;

constexpr const char* kHeader =
    "setting,frame,kind,geometry,geometry_share,seconds,speedup,traverse_seconds,raster_seconds,triangles,surfels,flip,"
    "flip_mean,flip_median,flip_max,foreground_psnr,psnr,ssim,hole_fraction,bloat_fraction,surfel_load_seconds,"
    "resolution_divisor,bvh_build_seconds";

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// `pbs eval` on the two-groups scene and its surfels, writing into a scratch folder. Tests that need the
// groups drawn as surfels pass --exhausted grow: arrays of 4000 surfels are too short for a group that
// fills a good part of even a 160-pixel view, and would be descended into.
// The groups are small enough that rays draw every node cheaper than its surfels: `--rays-cheaper keep` where a
// test needs surfels drawn.
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

// --texture-filter reaches every setting's frames and is recorded; the groups are untextured, so the errors are
// those of the default filtering (the filtering itself: TextureFiltering.NamedFilteringDrawsAsACameraCarryingIt).
TEST(EvalCli, TakesATextureFilter) {
  const EvalRun anisotropic, none;
  const std::string common = "--size 96x64 --frames 2 --peers embree=1 --sweep surfels --quiet";
  ASSERT_EQ(anisotropic.run(common).status, 0);
  const test::CommandResult run = none.run(common + " --texture-filter none");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(nlohmann::json::parse(test::readFile(anisotropic.out / "summary.json"))["texture_filter"], "anisotropic");
  EXPECT_EQ(nlohmann::json::parse(test::readFile(none.out / "summary.json"))["texture_filter"], "none");
  const std::vector<test::CsvRow> a = anisotropic.rows(), b = none.rows();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].fields.at("flip"), b[i].fields.at("flip"));
  EXPECT_EQ(none.run(common + " --texture-filter trilinear").status, 2);
}

// The .surfels file is read as frames draw it, one cache for the settings that draw its arrays: a far view
// reads only its prefixes, and reading is reported apart from the frames' times.
TEST(EvalCli, ReadsTheSurfelFileAsFramesDrawIt) {
  const EvalRun eval;
  const test::CommandResult run = eval.run(
      "--size 96x64 --frames 1 --orbit 30,20,12 --peers embree=1 "
      "--sweep surfels --sweep overdraw=2 --exhausted grow --quiet");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json summary = nlohmann::json::parse(test::readFile(eval.out / "summary.json"));
  const std::string file = eval.surfels.substr(1, eval.surfels.size() - 2);  // unquoted
  const auto bytesRead = summary["surfel_bytes_read"].get<std::uint64_t>();
  EXPECT_GT(bytesRead, 0u);
  EXPECT_LT(bytesRead, std::filesystem::file_size(file)) << "a far view draws short prefixes";
  EXPECT_GE(summary["surfels_read_seconds"].get<double>(), 0.0);
  for (const test::CsvRow& row : eval.rows()) {
    const bool peer = row.fields.at("setting") == "embree=1";
    if (peer) {
      EXPECT_EQ(row.number("surfel_load_seconds"), 0.0);
    } else {
      EXPECT_GT(row.number("surfels"), 0.0) << "the view must draw surfels for this test";
    }
  }
}

// Against the rasterizer's reference with no Embree setting, a glTF scene is opened without its mesh
// arrays and every frame reads the meshes it draws (the reference node by node): the same errors as
// with the scene read whole (which an Embree peer forces). The peer's BVHs serve the surfel frames' rays too,
// but the geometry's drawer is priced by the setting's own frames (EmbreeNodeCaster::drawnBefore): the same
// choices, the same images.
TEST(EvalCli, ExactReferenceReadsMeshesAsFramesDrawThem) {
  const EvalRun onDemand, whole;
  const std::string common =
      "--size 96x64 --frames 3 --path approach --reference exact --reference-samples 4 "
      "--sweep surfels --quiet --peers ";
  const test::CommandResult a = onDemand.run(common + "exact=1");
  ASSERT_EQ(a.status, 0) << a.err;
  const test::CommandResult b = whole.run(common + "exact=1 --peers embree=1");
  ASSERT_EQ(b.status, 0) << b.err;
  const nlohmann::json summaryA = nlohmann::json::parse(test::readFile(onDemand.out / "summary.json"));
  const nlohmann::json summaryB = nlohmann::json::parse(test::readFile(whole.out / "summary.json"));
  EXPECT_EQ(summaryA["meshes"], "read as frames draw them");
  EXPECT_EQ(summaryB["meshes"], "read whole");
  EXPECT_EQ(summaryA["reference"]["renderer"], "exact");
  EXPECT_EQ(summaryA["embree_build_seconds"], 0.0) << "no BVH over the whole scene";
  std::map<std::pair<std::string, std::string>, std::string> flipB;
  for (const test::CsvRow& row : whole.rows())
    flipB[{row.fields.at("setting"), row.fields.at("frame")}] = row.fields.at("flip");
  std::size_t compared = 0;
  for (const test::CsvRow& row : onDemand.rows()) {
    const auto key = std::pair(row.fields.at("setting"), row.fields.at("frame"));
    ASSERT_TRUE(flipB.contains(key)) << key.first;
    EXPECT_EQ(row.fields.at("flip"), flipB[key]) << key.first << " frame " << key.second;
    ++compared;
  }
  EXPECT_EQ(compared, 6u) << "exact=1 and surfels, three frames each";
  // The rays' BVHs are built by the first frame that draws a mesh by rays, and reported apart; with the
  // peer's BVH over the whole scene there is nothing to build.
  double builtOnDemand = 0.0, builtWhole = 0.0;
  bool raysOnDemand = false;
  for (const test::CsvRow& row : onDemand.rows()) {
    builtOnDemand += row.number("bvh_build_seconds");
    raysOnDemand = raysOnDemand || (row.fields.at("setting") == "surfels" && row.fields.at("geometry") == "rays");
  }
  for (const test::CsvRow& row : whole.rows()) builtWhole += row.number("bvh_build_seconds");
  EXPECT_EQ(raysOnDemand, builtOnDemand > 0.0);
  EXPECT_EQ(builtWhole, 0.0);
}

TEST(EvalCli, PeersSurfelsAndSweepsAgainstTheReference) {
  const EvalRun eval;
  const test::CommandResult run =
      eval.run("--size 96x64 --frames 2 --rays-cheaper keep --sweep overdraw=1 --sweep point=4 --quiet");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(run.err.empty()) << "--quiet: " << run.err;

  const test::CsvTable csv = readCsv(eval.out / "eval.csv");
  const std::vector<test::CsvRow>& rows = csv.rows;
  EXPECT_EQ(csv.header, kHeader);
  const std::vector<std::string> settings = {"embree=1", "embree=4",   "embree=16", "exact=1",
                                             "surfels",  "overdraw=1", "point=4"};
  ASSERT_EQ(rows.size(), settings.size() * 2);
  std::map<std::string, std::vector<const test::CsvRow*>> bySetting;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::string& name = rows[i].fields.at("setting");
    EXPECT_EQ(name, settings[i / 2]) << i;
    bySetting[name].push_back(&rows[i]);
    EXPECT_EQ(rows[i].number("frame"), double(i % 2)) << i;
    EXPECT_GE(rows[i].number("seconds"), 0.0);
    const std::string kind = rows[i].fields.at("kind");
    EXPECT_TRUE(kind == "near" || kind == "mid" || kind == "far") << kind;
    EXPECT_GE(rows[i].number("flip"), 0.0);
    EXPECT_LE(rows[i].number("flip"), 1.0);
    EXPECT_GT(rows[i].number("flip"), 0.0) << name << ": nothing but the reference itself has no error";
    const bool peer = name.rfind("embree", 0) == 0 || name.rfind("exact", 0) == 0;
    const std::string geometry = rows[i].fields.at("geometry");
    EXPECT_TRUE(geometry == "rays" || geometry == "raster") << name << ": " << geometry;
    if (peer) {
      EXPECT_EQ(rows[i].number("surfels"), 0.0) << name;
    } else {
      EXPECT_GT(rows[i].number("surfels"), 0.0) << name << ": a far, small scene draws surfels";
    }
  }
  for (std::size_t frame = 0; frame < 2; ++frame) {
    // More samples converge to the reference.
    EXPECT_LT(bySetting["embree=16"][frame]->number("flip"), bySetting["embree=1"][frame]->number("flip"));
    EXPECT_LT(bySetting["embree=4"][frame]->number("flip"), bySetting["embree=1"][frame]->number("flip"));
    // Speed-ups are over the faster of the 1-sample peers on that frame: that one scores exactly 1.
    const double rays = bySetting["embree=1"][frame]->number("speedup");
    const double raster = bySetting["exact=1"][frame]->number("speedup");
    EXPECT_EQ(std::max(rays, raster), 1.0);
    EXPECT_LE(std::min(rays, raster), 1.0);
  }

  const nlohmann::json summary = nlohmann::json::parse(test::readFile(eval.out / "summary.json"));
  for (const char* key :
       {"scene", "surfels", "path", "width", "height", "frames", "reference", "load_seconds", "surfels_load_seconds",
        "embree_build_seconds", "frame_kinds", "baseline", "settings", "pareto_front", "contact_sheet"})
    EXPECT_TRUE(summary.contains(key)) << key;
  EXPECT_EQ(summary["baseline"], "surfels");
  EXPECT_EQ(summary["path"], "orbit");
  EXPECT_EQ(summary["reference"]["samples"], 64);
  EXPECT_EQ(summary["frame_kinds"].size(), 2u);
  ASSERT_EQ(summary["settings"].size(), settings.size());
  for (std::size_t s = 0; s < settings.size(); ++s) {
    const nlohmann::json& entry = summary["settings"][s];
    EXPECT_EQ(entry["name"], settings[s]);
    ASSERT_TRUE(entry.contains("all")) << settings[s];
    for (const char* key : {"frames", "median_seconds", "median_speedup_over_fastest_exact", "median_flip",
                            "worst_flip", "worst_flip_frame", "median_flip_mean", "median_foreground_psnr",
                            "worst_foreground_psnr", "median_ssim", "median_hole_fraction", "worst_hole_fraction",
                            "median_bloat_fraction", "worst_bloat_fraction", "median_surfels", "median_triangles"})
      EXPECT_TRUE(entry["all"].contains(key)) << settings[s] << " " << key;
    EXPECT_EQ(entry["all"]["frames"], 2);
    // Every kind that occurs has its own summary, and the kinds' frames add up.
    int frames = 0;
    for (const char* kind : {"near", "mid", "far"})
      if (entry.contains(kind)) frames += entry[kind]["frames"].get<int>();
    EXPECT_EQ(frames, 2) << settings[s];
  }
  EXPECT_FALSE(summary["pareto_front"].empty());

  const std::string svg = test::readFile(eval.out / "error_vs_time.svg");
  ASSERT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_EQ(count(svg, "<circle class=\"marker\""), settings.size());
  for (const std::string& name : settings) EXPECT_NE(svg.find(">" + name + "</text>"), std::string::npos) << name;
  EXPECT_NE(svg.find("Embree rays"), std::string::npos) << "the peer's curve is drawn";

  const nlohmann::json& sheetRows = summary["contact_sheet"]["rows"];
  ASSERT_GE(sheetRows.size(), 2u);
  ASSERT_LE(sheetRows.size(), 4u);
  EXPECT_NE(std::find(sheetRows.begin(), sheetRows.end(), "surfels"), sheetRows.end());
  EXPECT_NE(std::find(sheetRows.begin(), sheetRows.end(), "embree=1"), sheetRows.end());
  const auto [w, h] = pngSize(eval.out / "contact_sheet.png");
  EXPECT_EQ(w, 3u * 96u);
  EXPECT_EQ(h, sheetRows.size() * 64u);
}

TEST(EvalCli, BadSweepsFailWithUsageErrors) {
  const EvalRun eval;
  const test::CommandResult unknown = eval.run("--sweep colour=1");
  EXPECT_EQ(unknown.status, 2);
  EXPECT_NE(unknown.err.find("unknown key 'colour'"), std::string::npos) << unknown.err;
  EXPECT_EQ(eval.run("--sweep overdraw=").status, 2);
  EXPECT_EQ(eval.run("--sweep overdraw=1,x").status, 2);
  EXPECT_EQ(eval.run("--sweep ordering=best").status, 2);
  EXPECT_EQ(eval.run("--sweep rays-near-share=1.5").status, 2) << "a share lies in [0, 1]";
  EXPECT_EQ(eval.run("--rays-near-share -0.1").status, 2);
  EXPECT_EQ(eval.run("--sweep embree=3").status, 2) << "samples per pixel are 1, 4, 16, 64 or 256";
  EXPECT_EQ(eval.run("--peers overdraw=2").status, 2) << "peers are exact renderers";
  EXPECT_EQ(eval.run("--reference-samples 8").status, 2);
  EXPECT_EQ(eval.run("--path sideways").status, 2);
  EXPECT_EQ(eval.run("--background 1,1").status, 2);
  EXPECT_EQ(eval.run("--size 10").status, 2);
  EXPECT_FALSE(std::filesystem::exists(eval.out / "eval.csv"));
}

// The baseline options (--point-size …) reach every setting: a combined setting equal to the baseline is
// measured once (the library's tests check what each setting draws).
TEST(EvalCli, BaselineOptionsApplyToEverySetting) {
  const EvalRun eval;
  const test::CommandResult run = eval.run(
      "--size 96x64 --frames 1 --peers exact=1 --reference-samples 4 --point-size 0.5 --exhausted grow --overdraw 4 "
      "--rays-cheaper keep "
      "--sweep overdraw=4 --sweep point=0.5+overdraw=4 --quiet");
  ASSERT_EQ(run.status, 0) << run.err;
  const std::vector<test::CsvRow> rows = eval.rows();
  ASSERT_EQ(rows.size(), 2u);  // exact=1 and surfels: both sweeps draw like the baseline
  EXPECT_EQ(rows[1].fields.at("setting"), "surfels");
  EXPECT_GT(rows[1].number("surfels"), 0.0);
  EXPECT_EQ(eval.run("--sweep point=1,2+threshold=3").status, 2) << "one value per key when combined";
  EXPECT_EQ(eval.run("--sweep geometry=sideways").status, 2);
}

// The CSV says what drew each frame's geometry: rays for Embree, the rasterizer for the exact peer, and for
// surfel frames the drawer their geometry nodes were given.
TEST(EvalCli, ReportsWhatDrewEachFramesGeometry) {
  const EvalRun eval;
  const test::CommandResult run = eval.run(
      "--size 96x64 --frames 2 --peers embree=1 --peers exact=1 --reference-samples 4 --orbit 30,20,1.2 "
      "--sweep geometry=raster,rays --quiet");
  ASSERT_EQ(run.status, 0) << run.err;
  std::map<std::string, std::set<std::string>> drawers;
  for (const test::CsvRow& row : eval.rows()) drawers[row.fields.at("setting")].insert(row.fields.at("geometry"));
  EXPECT_EQ(drawers["embree=1"], std::set<std::string>{"rays"});
  EXPECT_EQ(drawers["exact=1"], std::set<std::string>{"raster"});
  EXPECT_EQ(drawers["geometry=raster"], std::set<std::string>{"raster"});
  EXPECT_EQ(drawers["geometry=rays"], std::set<std::string>{"rays"});
}

TEST(EvalCli, SimplifiedMeshesAreMeasuredLikeSurfels) {
  const EvalRun eval;
  const test::CommandResult run =
      eval.run("--size 96x64 --frames 2 --peers exact=1 --reference-samples 4 --sweep simplify=0.5 --quiet");
  ASSERT_EQ(run.status, 0) << run.err;
  const std::vector<test::CsvRow> rows = eval.rows();
  ASSERT_EQ(rows.size(), 6u);  // exact=1, surfels, simplify=0.5; two frames each
  for (std::size_t i = 4; i < 6; ++i) {
    EXPECT_EQ(rows[i].fields.at("setting"), "simplify=0.5");
    EXPECT_EQ(rows[i].number("surfels"), 0.0) << "triangles in place of surfels";
    EXPECT_GT(rows[i].number("triangles"), 0.0);
    EXPECT_LT(rows[i].number("triangles"), rows[i - 4].number("triangles")) << "fewer than exact, same view";
    EXPECT_TRUE(std::isfinite(rows[i].number("flip")));
    EXPECT_TRUE(std::isfinite(rows[i].number("ssim")));
  }

  const nlohmann::json summary = nlohmann::json::parse(test::readFile(eval.out / "summary.json"));
  EXPECT_EQ(summary["baseline"], "surfels");
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

namespace pbs {
namespace {

// A budget of triangles plus surfels (`--budget-primitives`, the sweep key `primitives`) bounds what a
// frame draws, in render and in eval alike.
TEST(EvalCli, BudgetsBoundWhatFramesDraw) {
  const EvalRun eval;
  const test::CommandResult run =
      eval.run("--size 96x64 --frames 2 --peers exact=1 --reference-samples 4 --sweep primitives=6000 --quiet");
  ASSERT_EQ(run.status, 0) << run.err;
  std::size_t budgeted = 0;
  for (const test::CsvRow& row : eval.rows()) {
    if (row.fields.at("setting") != "primitives=6000") continue;
    ++budgeted;
    EXPECT_LE(row.number("triangles") + row.number("surfels"), 6000.0);
    EXPECT_GT(row.number("triangles") + row.number("surfels"), 0.0);
  }
  EXPECT_EQ(budgeted, 2u);
  const test::CommandResult frame = test::runPbs("render " + eval.scene + " --surfels " + eval.surfels +
                                                 " --size 96x64 --budget-primitives 6000 --json");
  ASSERT_EQ(frame.status, 0) << frame.err;
  const nlohmann::json drawn = nlohmann::json::parse(frame.out);
  EXPECT_LE(drawn["triangles"].get<double>() + drawn["surfels"].get<double>(), 6000.0);
  EXPECT_EQ(eval.run("--sweep primitives=0").status, 2);
}

// `pbs calibrate` writes a calibration file that `--budget-ms --calibration` reads; frames then report the
// limit and the prediction, the feedback corrects it between frames, and a file without its costs is
// refused by name.
TEST(EvalCli, CalibrateWritesWhatABudgetInMillisecondsReads) {
  const EvalRun eval;
  const std::filesystem::path calibration = eval.scratch / "calibration.json";
  const test::CommandResult made =
      test::runPbs("calibrate " + eval.scene + " --surfels " + eval.surfels +
                   " --size 96x64 --frames 1 --repeats 1 -q -o '" + calibration.string() + "'");
  ASSERT_EQ(made.status, 0) << made.err;
  EXPECT_NE(made.out.find("median error"), std::string::npos) << made.out;
  const nlohmann::json file = nlohmann::json::parse(test::readFile(calibration));
  EXPECT_EQ(file["pbs_frame_costs"], 2);
  EXPECT_GT(file["seconds_per"]["upscale_pixel"].get<double>(), 0.0) << "the upscale is timed";
  EXPECT_EQ(file["frames"].size(), 36u) << "12 cuts of one view of each of the three paths";

  const std::string render = "render " + eval.scene + " --surfels " + eval.surfels + " --size 96x64 --budget-ms 20 ";
  const test::CommandResult frames =
      test::runPbs(render + "--calibration '" + calibration.string() + "' --frames 3 --budget-feedback --json");
  ASSERT_EQ(frames.status, 0) << frames.err;
  const nlohmann::json report = nlohmann::json::parse(frames.out);
  ASSERT_EQ(report["frames"].size(), 3u);
  EXPECT_DOUBLE_EQ(report["frames"][0]["budget_limit_seconds"].get<double>(), 0.020) << "no frame to correct by yet";
  for (const nlohmann::json& frame : report["frames"]) EXPECT_GT(frame["predicted_seconds"].get<double>(), 0.0);

  test::writeFile(eval.scratch / "bad.json", R"({"pbs_frame_costs": 1, "seconds_per": {}})");
  const test::CommandResult bad = test::runPbs(render + "--calibration '" + (eval.scratch / "bad.json").string() + "'");
  EXPECT_EQ(bad.status, 1);
  EXPECT_NE(bad.err.find("bad.json: seconds_per.image_pixel: missing"), std::string::npos) << bad.err;
  EXPECT_EQ(
      test::runPbs("render " + eval.scene + " --surfels " + eval.surfels + " --size 96x64 --budget-feedback").status, 2)
      << "feedback corrects a budget in milliseconds";
  EXPECT_EQ(test::runPbs(render + "--budget-primitives 5000").status, 2) << "one budget at a time";
  const test::CommandResult swept =
      eval.run("--size 96x64 --frames 1 --peers exact=1 --reference-samples 4 --sweep ms=20 --quiet");
  ASSERT_EQ(swept.status, 0) << swept.err;
  const std::vector<test::CsvRow> rows = eval.rows();
  EXPECT_EQ(std::count_if(rows.begin(), rows.end(),
                          [](const test::CsvRow& row) { return row.fields.at("setting") == "ms=20"; }),
            1);
}

// A budget in milliseconds that no cut fits draws at a lower resolution and writes the frame at its size; the
// JSON says by how much. `--budget-resolution full` keeps the resolution, and needs a budget in milliseconds.
TEST(EvalCli, ABudgetTooSmallForAnyCutLowersTheResolution) {
  const EvalRun eval;
  const std::string render = "render " + eval.scene + " --surfels " + eval.surfels + " --size 96x64 ";
  const std::filesystem::path image = eval.scratch / "budget.png";
  const test::CommandResult lowered = test::runPbs(render + "--budget-ms 0.000001 --json -o '" + image.string() + "'");
  ASSERT_EQ(lowered.status, 0) << lowered.err;
  EXPECT_EQ(nlohmann::json::parse(lowered.out)["resolution_divisor"].get<double>(), 8.0);
  EXPECT_EQ(pngSize(image), (std::pair<std::uint32_t, std::uint32_t>{96, 64}));
  const test::CommandResult full = test::runPbs(render + "--budget-ms 0.000001 --budget-resolution full --json");
  ASSERT_EQ(full.status, 0) << full.err;
  EXPECT_EQ(nlohmann::json::parse(full.out)["resolution_divisor"].get<double>(), 1.0);
  EXPECT_EQ(test::runPbs(render + "--budget-resolution full").status, 2) << "it qualifies --budget-ms";
  EXPECT_EQ(test::runPbs(render + "--budget-ms 5 --budget-resolution half").status, 2);
}

}  // namespace
}  // namespace pbs
