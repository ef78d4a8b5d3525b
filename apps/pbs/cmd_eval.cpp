// `pbs eval SCENE --surfels F -o DIR`: error against run time. An orbit rendered exactly once as the
// reference, then every setting of a sweep over the same views, timed and compared with it; written
// as DIR/eval.csv, DIR/summary.json, DIR/error_vs_time.svg and DIR/contact_sheet.png. Simplified
// meshes (simplify=R) are measured the same way, as the alternative to surfels.
#include "commands.hpp"
#include "contact_sheet.hpp"
#include "eval_outputs.hpp"
#include "eval_run.hpp"
#include "eval_settings.hpp"
#include "image_files.hpp"
#include "orbit_views.hpp"
#include "progress_meter.hpp"
#include "report_numbers.hpp"
#include "scene_report.hpp"
#include "svg_plot.hpp"

#include <pbs/raster/thread_arena.hpp>
#include <pbs/scene/simplified_meshes.hpp>
#include <pbs/surfels/surfel_file.hpp>
#include <pbs/surfels/surfelize.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>

namespace pbs::cli {
namespace {

struct EvalOptions {
  std::string scene;
  std::string surfels;
  std::string output;
  std::vector<std::string> sweeps;
  std::uint32_t frames = 24;
  std::string size = "1920x1080";
  std::string orbit = "30,20,2.5";
  LodOptions baseline;  // what every setting starts from
  CaptureSource captureFrom = CaptureSource::Auto;
  bool quiet = false;
  int threads = 0;
};

// The file's own arrays, and those of other orderings made on demand with the file's options.
class SurfelSources {
 public:
  SurfelSources(const LoadedScene& loaded, const std::string& file, CaptureSource source, bool quiet)
      : loaded_(loaded), source_(source), quiet_(quiet) {
    options_ = SurfelFileReader(file).options();
    own_ = loadSceneSurfels(file, loaded.scene, loaded.hierarchy);
  }

  SurfelOrdering fileOrdering() const { return options_.ordering; }

  const SceneSurfels& of(const EvalSetting& setting) {
    if (!setting.ordering || *setting.ordering == options_.ordering) return own_;
    auto found = made_.find(*setting.ordering);
    if (found != made_.end()) return found->second;
    SurfelizeOptions settings;
    settings.file = options_;
    settings.file.ordering = *setting.ordering;
    settings.source = source_;
    const std::string name(orderingName(*setting.ordering));
    ProgressMeter meter("surfelize " + name, ProgressMeter::styleFor(quiet_));
    settings.onProgress = [&](const SurfelizeProgress& p) {
      meter.update(double(p.arraysDone) / double(std::max<std::uint32_t>(p.arraysTotal, 1)),
                   std::to_string(p.arraysDone) + "/" + std::to_string(p.arraysTotal) + " arrays");
    };
    SurfelizeStats stats;
    const SurfelFile file = surfelize(loaded_.scene, loaded_.hierarchy, settings, &stats);
    if (stats.arrays > 0) meter.finish(std::to_string(stats.arrays) + " arrays, " + withThousands(stats.surfels) + " surfels");
    return made_.emplace(*setting.ordering, sceneSurfelsOf(file, loaded_.scene, loaded_.hierarchy, "ordering=" + name))
        .first->second;
  }

 private:
  const LoadedScene& loaded_;
  CaptureSource source_;
  bool quiet_;
  SurfelFileOptions options_;
  SceneSurfels own_;
  std::map<SurfelOrdering, SceneSurfels> made_;
};

// Simplified copies of the scene, one per ratio a sweep names, made before timing starts; the time
// each took is reported in summary.json apart from the frames'.
class SimplifiedScenes {
 public:
  SimplifiedScenes(const Scene& scene, bool quiet) : scene_(scene), quiet_(quiet) {}

  const Scene& of(const EvalSetting& setting) {
    const double ratio = *setting.simplify;
    auto found = made_.find(ratio);
    if (found != made_.end()) return found->second.simplified.scene;
    ProgressMeter meter(setting.name, ProgressMeter::styleFor(quiet_));
    SimplifyOptions options;
    options.ratio = ratio;
    const auto start = std::chrono::steady_clock::now();
    Made made{simplifyScene(scene_, options), 0.0};
    made.seconds = secondsSince(start);
    meter.finish(withThousands(made.simplified.trianglesBefore) + " → " +
                 withThousands(made.simplified.trianglesAfter) + " mesh triangles");
    return made_.emplace(ratio, std::move(made)).first->second.simplified.scene;
  }

  // Per ratio: its time, the meshes' triangles (each mesh once) before and after, the largest relative
  // deformation reached and the error bound simplification stopped at.
  nlohmann::json json() const {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& [ratio, made] : made_) {
      const SimplifiedScene& s = made.simplified;
      list.push_back({{"ratio", ratio},
                      {"seconds", made.seconds},
                      {"mesh_triangles_before", s.trianglesBefore},
                      {"mesh_triangles_after", s.trianglesAfter},
                      {"kept_fraction",
                       s.trianglesBefore > 0 ? double(s.trianglesAfter) / double(s.trianglesBefore) : 1.0},
                      {"largest_error", s.largestError},
                      {"target_error", SimplifyOptions{}.targetError}});
    }
    return list;
  }

 private:
  struct Made {
    SimplifiedScene simplified;
    double seconds = 0.0;
  };
  const Scene& scene_;
  bool quiet_;
  std::map<double, Made> made_;
};

std::string psnrText(double psnr) {
  if (!std::isfinite(psnr)) return "inf";
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", psnr);
  return text;
}

void printTable(const std::vector<EvalSummary>& summaries, const EvalSummary& reference) {
  std::printf("%-18s %9s %8s %12s %12s %13s %15s %9s\n", "setting", "median ms", "speed-up", "surfels", "triangles",
              "PSNR med/min", "SSIM med/min", "holes");
  for (const EvalSummary& s : summaries) {
    const std::string psnr = psnrText(s.medianPsnr) + "/" + psnrText(s.worstPsnr);
    std::printf("%-18s %9.2f %7.2fx %12s %12s %13s %7.4f/%.4f %9.2e\n", s.name.c_str(), s.medianSeconds * 1e3,
                s.medianSeconds > 0 ? reference.medianSeconds / s.medianSeconds : 0.0,
                withThousands(std::uint64_t(s.medianSurfels)).c_str(),
                withThousands(std::uint64_t(s.medianTriangles)).c_str(), psnr.c_str(), s.medianSsim, s.worstSsim,
                s.medianHoleFraction);
  }
}

void run(const EvalOptions& options) {
  const Orbit orbit = parseOrbit(options.orbit);
  const auto [width, height] = parseSize(options.size);
  const LoadedScene loaded = loadAndAnalyze(options.scene, LoadOptions{});
  SurfelSources sources(loaded, options.surfels, options.captureFrom, options.quiet);
  const LodOptions& baseline = options.baseline;
  const std::vector<EvalSetting> settings = evalSettings(
      options.sweeps.empty() ? defaultSweep(sources.fileOrdering()) : options.sweeps, baseline);
  const std::optional<std::size_t> baselineIndex = baselineSetting(settings, baseline);
  // Arrays of other orderings and simplified meshes are made before timing starts, so no frame waits on them.
  SimplifiedScenes simplifiedScenes(loaded.scene, options.quiet);
  for (const EvalSetting& setting : settings) {
    if (!setting.exact) sources.of(setting);
    if (setting.simplify) simplifiedScenes.of(setting);
  }

  const std::vector<OrbitView> views = orbitViews(loaded.summary.bounds, orbit, options.frames, width, height);
  ProgressMeter meter("eval", ProgressMeter::styleFor(options.quiet));
  const EvalResults results = runEval(
      loaded.scene, loaded.hierarchy, views, settings, [&](const EvalSetting& s) -> const SceneSurfels& { return sources.of(s); },
      [&](const EvalSetting& s) -> const Scene& { return simplifiedScenes.of(s); },
      [&](std::size_t done, std::size_t total, const std::string& detail) {
        meter.update(double(done) / double(total), detail);
      });
  meter.finish(std::to_string(settings.size()) + " settings × " + std::to_string(views.size()) + " frames");

  std::vector<EvalSummary> summaries;
  for (std::size_t s = 0; s < settings.size(); ++s) summaries.push_back(summarize(settings[s].name, results.settings[s].frames));
  const EvalSummary reference = summarize("exact reference", results.reference);

  const std::filesystem::path folder(options.output);
  std::filesystem::create_directories(folder);
  writeTextFile(folder / "eval.csv", evalCsv(settings, results));
  nlohmann::json summary =
      summaryJson(EvalRunInfo{.scene = loaded.name, .surfels = options.surfels, .width = width, .height = height,
                              .frames = std::uint32_t(views.size()), .orbit = orbit, .baseline = baselineIndex},
                  summaries, reference);
  summary["simplification"] = simplifiedScenes.json();
  writeTextFile(folder / "error_vs_time.svg", renderSvg(errorTimePlot(settings, summaries, baselineIndex)));

  // Contact sheet of frame 0: exact | setting | |difference| × kDifferenceGain, one row per setting shown.
  const std::vector<std::size_t> rows = sheetSettings(settings, summaries, baselineIndex);
  std::vector<std::span<const std::uint8_t>> tiles;
  for (std::size_t s : rows) {
    tiles.emplace_back(results.referenceFirst);
    tiles.emplace_back(results.settings[s].firstImage);
    tiles.emplace_back(results.settings[s].firstDifference);
    summary["contact_sheet"]["rows"].push_back(settings[s].name);
  }
  summary["contact_sheet"]["file"] = "contact_sheet.png";
  summary["contact_sheet"]["difference_gain"] = kDifferenceGain;
  const std::uint8_t background[3] = {235, 235, 235};
  writeImage8(folder / "contact_sheet.png", 3 * width, std::uint32_t(rows.size()) * height, 3,
              contactSheet(width, height, 3, tiles, background));
  writeTextFile(folder / "summary.json", summary.dump(2) + "\n");

  std::printf("%s: %ux%u, %zu frames, exact reference median %.2f ms\n", loaded.name.c_str(), width, height,
              views.size(), reference.medianSeconds * 1e3);
  printTable(summaries, reference);
  std::printf("wrote %s/{eval.csv, summary.json, error_vs_time.svg, contact_sheet.png}\n", folder.string().c_str());
}

}  // namespace

void addEvalCommand(CLI::App& app) {
  auto options = std::make_shared<EvalOptions>();
  CLI::App* command = app.add_subcommand(
      "eval", "Error against run time: sweep LOD settings over an orbit and compare every frame with exact rendering");
  command->add_option("scene", options->scene, "a .gltf/.glb file, or 'default'")->required();
  command->add_option("--surfels", options->surfels, "the scene's .surfels file (from pbs surfelize)")->required();
  command->add_option("-o,--output", options->output,
                      "folder for eval.csv, summary.json, error_vs_time.svg, contact_sheet.png (created if missing)")
      ->required();
  command->add_option("--sweep", options->sweeps,
                      "KEY=V1,V2,… or KEY=V+KEY=V (keys: " + sweepKeys() +
                          "), repeatable; each value one setting over the baseline LOD options (--threshold, --point-size, "
                          "…). Default: "
                          "overdraw=1,2,4,8 threshold=64,256 point=1,4, the file's other orderings and "
                          "simplify=0.25,0.05,0.01 (meshes simplified to that fraction of their triangles, drawn in "
                          "place of surfels). 'exact' always comes first");
  addLodOptions(*command, options->baseline);
  command->add_option("--frames", options->frames, "views on the orbit")->check(CLI::Range(1u, 100000u))->capture_default_str();
  command->add_option("--size", options->size, "WxH pixels")->capture_default_str();
  command->add_option("--orbit", options->orbit, "AZ,EL,DIST: degrees, degrees, distance in bounding radii")
      ->capture_default_str();
  addCaptureSourceOption(*command, options->captureFrom,
                         "how arrays of other orderings are made on demand (the .surfels file does not record it: "
                         "give what it was made with)");
  command->add_flag("-q,--quiet", options->quiet, "no progress on stderr");
  addThreadsOption(*command, options->threads);
  command->callback([options] { runWithThreads(options->threads, [&] { run(*options); }); });
}

}  // namespace pbs::cli
