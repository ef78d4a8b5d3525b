// `pbs calibrate SCENE --surfels F`: times frames of the three camera paths under cuts from coarse to
// fine and fits what a frame costs on this machine (FrameCosts), for `--budget-ms --calibration FILE`.
#include "commands.hpp"
#include "orbit_views.hpp"
#include "progress_meter.hpp"
#include "scene_report.hpp"

#include <pbs/evaluation/frame_calibration.hpp>
#include <pbs/evaluation/svg_plot.hpp>
#include <pbs/raster/thread_arena.hpp>
#include <pbs/surfels/surfel_cache.hpp>

#include <cstdio>
#include <iostream>
#include <memory>

namespace pbs::cli {
namespace {

struct CalibrateOptions {
  std::string scene;
  std::string surfels;
  std::string size = "1920x1080";
  std::string output = "calibration.json";
  std::uint32_t frames = 6;
  std::uint32_t repeats = 2;
  // A budget asks that frames finish within it, and the costs are fitted to frames unlike a path's (repeated,
  // in no path): 0.9 held 21–22 of the default scene's 24 approach frames within 33 ms and 19 of the city's,
  // 0.75 held 19 and 12–19 (docs/performance.md).
  double quantile = 0.9;
  LodOptions lod;
  std::uint64_t cacheMb = 1024;
  bool json = false;
  bool quiet = false;
  int threads = 0;
};

void run(const CalibrateOptions& options) {
  const auto [width, height] = parseSize(options.size);
  SurfelFileReader file(options.surfels);
  LoadedScene loaded = loadAndAnalyze(options.scene, LoadOptions{}, file);
  SurfelCache surfels(std::move(file), loaded.scene, loaded.hierarchy, options.cacheMb << 20);
  std::vector<Camera> cameras;
  for (const char* path : {"orbit", "approach", "flythrough"})
    for (const PathView& view : pathViews(loaded, path, parseOrbit("30,20,2.5"), options.frames, width, height))
      cameras.push_back(view.camera);
  const std::vector<CalibrationCut> cuts = calibrationCuts(options.lod);
  const FrameCalibration calibration =
      calibrateFrameCosts(loaded.scene, loaded.hierarchy, {.cache = &surfels}, cameras, cuts, options.repeats,
                          options.quantile, progressMeters(options.quiet));
  const nlohmann::json json = calibrationJson(calibration);
  writeTextFile(options.output, json.dump(2) + "\n");
  if (options.json) {
    std::cout << json.dump(2) << "\n";
    return;
  }
  const FrameCosts& c = calibration.fit.costs;
  std::printf("%s: %zu frames at %ux%u (%zu cuts of %zu views)\n", loaded.name.c_str(), calibration.frames.size(),
              width, height, cuts.size(), cameras.size());
  std::printf(
      "ns per image pixel %.2f, surfel %.2f, surfel pixel %.2f, node %.0f, node a budget weighs %.0f, upscaled pixel "
      "%.2f\n",
      c.perImagePixel * 1e9, c.perSurfel * 1e9, c.perSurfelPixel * 1e9, c.perNode * 1e9, c.perNodeWeighed * 1e9,
      c.upscalePerPixel * 1e9);
  std::printf(
      "geometry by the rasterizer (%zu frames): ns per triangle %.2f (more %.2f if on pixels), covered pixel %.2f, box "
      "pixel %.2f, node %.0f\n",
      calibration.fit.rasterFrames, c.rasterPerTriangle * 1e9, c.rasterPerTriangleOnPixels * 1e9,
      c.rasterPerPixel * 1e9, c.rasterPerBoxPixel * 1e9, c.rasterPerNode * 1e9);
  std::printf(
      "geometry by rays (%zu frames): ns per image pixel %.2f, covered pixel %.2f, box pixel level %.2f, node %.0f\n",
      calibration.fit.rayFrames, c.raysPerImagePixel * 1e9, c.raysPerPixel * 1e9, c.raysPerBoxPixel * 1e9,
      c.raysPerNode * 1e9);
  std::printf(
      "predicted against measured: median error %.1f %%, 90th percentile %.1f %% (least squares × %.2f, so "
      "that %.0f %% of the frames take no longer than predicted)\n",
      calibration.fit.medianError * 100.0, calibration.fit.p90Error * 100.0, calibration.fit.scale,
      calibration.fit.quantile * 100.0);
  std::printf("wrote %s\n", options.output.c_str());
}

}  // namespace

void addCalibrateCommand(CLI::App& app) {
  auto options = std::make_shared<CalibrateOptions>();
  CLI::App* command = app.add_subcommand(
      "calibrate", "Time frames under cuts from coarse to fine and fit what a frame costs here, for --budget-ms");
  command->add_option("scene", options->scene, "a .gltf/.glb file, or 'default'")->required();
  command->add_option("--surfels", options->surfels, "the scene's .surfels file (from pbs surfelize)")->required();
  command->add_option("--size", options->size, "WxH pixels, as the budgeted frames will have")->capture_default_str();
  command->add_option("--frames", options->frames, "views of each camera path (orbit, approach, flythrough)")
      ->check(CLI::Range(1u, 1000u))
      ->capture_default_str();
  command->add_option("--repeats", options->repeats, "renders of each frame; the median counts (the slower of two)")
      ->check(CLI::Range(1u, 100u))
      ->capture_default_str();
  command
      ->add_option("--quantile", options->quantile,
                   "the share of the timed frames the fitted costs predict to take at least what they took (0.5: "
                   "unbiased at the median; higher: a budget overshot less often, at a lower resolution)")
      ->check(CLI::Range(0.5, 1.0))
      ->capture_default_str();
  command->add_option("-o,--output", options->output, "the calibration file (JSON)")->capture_default_str();
  addLodOptions(*command, options->lod);
  addCacheOption(*command, options->cacheMb, "surfels are read as frames draw them, up to this many MB");
  command->add_flag("--json", options->json, "print the calibration file's JSON");
  command->add_flag("-q,--quiet", options->quiet, "no progress meters on stderr");
  addThreadsOption(*command, options->threads);
  command->callback([options] { runWithThreads(options->threads, [&] { run(*options); }); });
}

}  // namespace pbs::cli
