// `pbs demo`: the main job on the embedded default scene, end to end: generate and summarise it, make
// surfels for every complex node, render one view with them and exactly, and compare the two.
#include "commands.hpp"
#include "image_files.hpp"
#include "progress_meter.hpp"
#include "report_numbers.hpp"
#include "scene_report.hpp"

#include <pbs/raster/headlight_shading.hpp>
#include <pbs/raster/image_metrics.hpp>
#include <pbs/raster/orbit_camera.hpp>
#include <pbs/raster/thread_arena.hpp>
#include <pbs/surfels/frame_renderer.hpp>
#include <pbs/surfels/scene_surfels.hpp>
#include <pbs/surfels/surfelize.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

namespace pbs::cli {
namespace {

struct DemoOptions {
  std::string scene = "default";
  std::string output = "pbs-demo";
  SurfelizeOptions surfelize;
  std::uint32_t width = 1920, height = 1080;
  bool json = false;
  int threads = 0;
};

RgbaImage asImage(std::uint32_t width, std::uint32_t height, std::vector<glm::vec4> pixels) {
  return RgbaImage{width, height, std::move(pixels)};
}

void run(const DemoOptions& options) {
  const LoadedScene loaded = loadAndAnalyze(options.scene, LoadOptions{});
  const std::filesystem::path folder(options.output);
  std::filesystem::create_directories(folder);

  ProgressMeter meter("surfelize", ProgressMeter::styleFor(options.json));
  SurfelizeOptions settings = options.surfelize;
  settings.onProgress = [&](const SurfelizeProgress& p) {
    meter.update(double(p.arraysDone) / double(std::max(p.arraysTotal, 1u)),
                 std::to_string(p.arraysDone) + "/" + std::to_string(p.arraysTotal) + " arrays");
  };
  auto start = std::chrono::steady_clock::now();
  SurfelizeStats stats;
  const SurfelFile file = surfelize(loaded.scene, loaded.hierarchy, settings, &stats);
  const double surfelizeSeconds = secondsSince(start);
  if (stats.arrays > 0) meter.finish(std::to_string(stats.arrays) + " arrays");
  writeSurfelFile(folder / "default.surfels", file);
  const SceneSurfels surfels = sceneSurfelsOf(file, loaded.scene, loaded.hierarchy, loaded.name);

  const Bounds& bounds = loaded.summary.bounds;
  const Camera camera =
      orbitCamera(bounds.center(), 0.5 * glm::length(bounds.size()), Orbit{}, options.width, options.height);
  FrameRenderer withSurfels(loaded.scene, loaded.hierarchy, {.mode = RenderMode::Surfels, .lod = {}}, options.width,
                            options.height, {.surfels = &surfels});
  FrameRenderer exactly(loaded.scene, loaded.hierarchy, {.mode = RenderMode::Exact, .lod = {}}, options.width,
                        options.height);
  const FrameResult fast = withSurfels.render(camera);
  const FrameResult exact = exactly.render(camera);
  writeImage8(folder / "surfels.png", options.width, options.height, 4, toRgba8(fast.image));
  writeImage8(folder / "exact.png", options.width, options.height, 4, toRgba8(exact.image));
  const ImageDifference difference = compareImages(asImage(options.width, options.height, exact.image),
                                                   asImage(options.width, options.height, fast.image));

  if (options.json) {
    nlohmann::json report = summaryJson(loaded);
    report["surfel_nodes"] = stats.nodesWithSurfels;
    report["arrays"] = stats.arrays;
    report["surfels"] = stats.surfels;
    report["surfelize_seconds"] = surfelizeSeconds;
    report["frame"] = {{"width", options.width},
                       {"height", options.height},
                       {"surfels_seconds", fast.seconds},
                       {"exact_seconds", exact.seconds},
                       {"surfels_drawn", fast.stats.surfels},
                       {"triangles_drawn", fast.stats.triangles},
                       {"exact_triangles", exact.stats.triangles},
                       {"psnr", finiteOrNull(difference.psnr)},
                       {"ssim", difference.ssim},
                       {"hole_fraction", difference.holeFraction}};
    report["output"] = folder.string();
    std::cout << report.dump(2) << "\n";
    return;
  }
  printSummary(loaded);
  std::printf("surfelize  %s nodes above %s triangles share %s arrays: %s surfels in %.1f s (capture %u px)\n",
              withThousands(stats.nodesWithSurfels).c_str(), withThousands(settings.file.threshold).c_str(),
              withThousands(stats.arrays).c_str(), withThousands(stats.surfels).c_str(), surfelizeSeconds,
              settings.file.resolution);
  std::printf("render     %ux%u: surfels %.1f ms (%s surfels, %s triangles), exact %.1f ms (%s triangles): %.1fx\n",
              options.width, options.height, fast.seconds * 1e3, withThousands(fast.stats.surfels).c_str(),
              withThousands(fast.stats.triangles).c_str(), exact.seconds * 1e3,
              withThousands(exact.stats.triangles).c_str(), exact.seconds / std::max(fast.seconds, 1e-9));
  std::printf("compare    PSNR %.1f dB, SSIM %.4f, holes %.4f (surfels against exact)\n", difference.psnr,
              difference.ssim, difference.holeFraction);
  std::printf("wrote      %s/{default.surfels, surfels.png, exact.png}\n", folder.string().c_str());
}

}  // namespace

void addDemoCommand(CLI::App& app) {
  auto options = std::make_shared<DemoOptions>();
  // The demo captures at 256 px (surfelize's default is 512): a quarter of the work, so the whole
  // pipeline runs in well under a minute on two cores.
  options->surfelize.file.resolution = 256;
  SurfelFileOptions& file = options->surfelize.file;
  CLI::App* command = app.add_subcommand(
      "demo", "The main job on the embedded default scene (or SCENE): surfelize, render with surfels and exactly, compare");
  command->add_option("scene", options->scene, "a .gltf/.glb file, or 'default'")->capture_default_str();
  command->add_option("-o,--output", options->output, "folder for the .surfels file and the two images")
      ->capture_default_str();
  command->add_option("--threshold", file.threshold, "nodes above this many triangles get surfels")
      ->capture_default_str();
  command->add_option("--max-surfels", file.maxSurfels, "surfels per array at most")
      ->check(CLI::Range(1u, 1u << 26))
      ->capture_default_str();
  addCaptureOptions(*command, file.resolution, file.directions);
  command->add_option("--width", options->width, "image width")->check(CLI::Range(1u, 16384u))->capture_default_str();
  command->add_option("--height", options->height, "image height")->check(CLI::Range(1u, 16384u))->capture_default_str();
  command->add_flag("--json", options->json, "print JSON instead of text");
  addThreadsOption(*command, options->threads);
  command->callback([options] { runWithThreads(options->threads, [&] { run(*options); }); });
}

}  // namespace pbs::cli
