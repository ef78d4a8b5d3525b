// `pbs demo`: the main job on the embedded default scene, end to end: generate and summarise it, make
// surfels for every complex node, render one view with them and with Embree's rays, and measure both
// against a converged reference.
#include "commands.hpp"
#include "image_files.hpp"
#include "progress_meter.hpp"
#include <pbs/evaluation/report_numbers.hpp>
#include <pbs/evaluation/view_draws.hpp>
#include "scene_report.hpp"

#include <pbs/raster/headlight_shading.hpp>
#include <pbs/raster/image_metrics.hpp>
#include <pbs/raster/orbit_camera.hpp>
#include <pbs/raster/raster_limits.hpp>
#include <pbs/raster/thread_arena.hpp>
#include <pbs/scene/embree_caster.hpp>
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
  OctreeChoice octree;
  std::uint32_t width = 1920, height = 1080;
  bool json = false;
  int threads = 0;
};

// The converged reference every frame of the demo is measured against, as `pbs eval`'s default.
constexpr std::uint32_t kReferenceSamples = 64;
// Draws of the view whose median time the report gives for each renderer but the reference.
constexpr int kTimedFrames = 5;

struct DemoFrame {
  const char* name;
  FrameResult frame;
};

void run(const DemoOptions& options) {
  LoadedScene loaded = loadAndAnalyze(options.scene, LoadOptions{});
  SurfelizeOptions settings = options.surfelize;
  // A flat scene is rebuilt as a loose octree, as surfelize would.
  settings.file.octreeLeafTriangles = options.octree.leavesFor(loaded.scene);
  if (settings.file.octreeLeafTriangles > 0) {
    loaded.scene = asLooseOctree(loaded.scene, settings.file.octreeLeafTriangles, loaded.name);
    loaded.hierarchy = analyzeHierarchy(loaded.scene);
    loaded.summary = summarizeScene(loaded.scene, loaded.hierarchy);
  }
  const std::filesystem::path folder(options.output);
  std::filesystem::create_directories(folder);

  ProgressMeter meter("surfelize", ProgressMeter::styleFor(options.json));
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
  // The surfels against the exact renderer a user without a GPU has, Embree's rays at 1 and 4 samples
  // per pixel, all measured against the converged reference: rays at kReferenceSamples.
  const EmbreeScene rays(loaded.scene, loaded.hierarchy);
  LodOptions lod;
  applyCommandLodDefaults(lod);
  // A frame's time is the median of kTimedFrames draws of the view: the first draw of a process pays
  // for faulting in its buffers (the image alone is 33 MB at 1920×1080), which a viewer pays once.
  const auto frameOf = [&](RenderMode mode, std::uint32_t samples, int draws) {
    FrameRenderer renderer(loaded.scene, loaded.hierarchy, {.mode = mode, .lod = lod, .samples = samples},
                           options.width, options.height, {.surfels = &surfels, .simplified = nullptr, .rays = &rays});
    ViewDraws drawn = drawView(renderer, camera, draws, [](const FrameResult& frame) { return frame.seconds; });
    drawn.first.seconds = drawn.byTime[drawn.byTime.size() / 2].seconds;
    return std::move(drawn.first);
  };
  const FrameResult reference = frameOf(RenderMode::Embree, kReferenceSamples, 1);
  const DemoFrame frames[] = {{"surfels", frameOf(RenderMode::Surfels, 1, kTimedFrames)},
                              {"embree, 1 sample", frameOf(RenderMode::Embree, 1, kTimedFrames)},
                              {"embree, 4 samples", frameOf(RenderMode::Embree, 4, kTimedFrames)}};
  writeImage8(folder / "reference.png", options.width, options.height, 4, toRgba8(reference.image));
  writeImage8(folder / "surfels.png", options.width, options.height, 4, toRgba8(frames[0].frame.image));
  writeImage8(folder / "embree.png", options.width, options.height, 4, toRgba8(frames[1].frame.image));
  const RgbaImage referenceImage{options.width, options.height, reference.image};
  std::vector<ImageDifference> errors;
  for (const DemoFrame& f : frames)
    errors.push_back(compareImages(RgbaImage{options.width, options.height, f.frame.image}, referenceImage));
  const FrameResult& fast = frames[0].frame;
  const double speedup = frames[1].frame.seconds / std::max(fast.seconds, 1e-9);

  if (options.json) {
    nlohmann::json report = summaryJson(loaded);
    report["surfel_nodes"] = stats.nodesWithSurfels;
    report["arrays"] = stats.arrays;
    report["surfels"] = stats.surfels;
    report["surfelize_seconds"] = surfelizeSeconds;
    report["frame"] = {{"width", options.width},
                       {"height", options.height},
                       {"reference_samples", kReferenceSamples},
                       {"reference_seconds", reference.seconds},
                       {"draws_per_time", kTimedFrames},
                       {"surfels_drawn", fast.stats.surfels},
                       {"triangles_drawn", fast.stats.triangles},
                       {"surfels_speedup_over_embree", speedup}};
    const char* keys[] = {"surfels", "embree_1", "embree_4"};
    for (std::size_t i = 0; i < std::size(frames); ++i)
      report["frame"][keys[i]] = {{"seconds", frames[i].frame.seconds},
                                  {"flip", errors[i].flipForegroundMean},
                                  {"foreground_psnr", finiteOrNull(errors[i].foregroundPsnr)},
                                  {"ssim", errors[i].ssim},
                                  {"hole_fraction", errors[i].holeFraction},
                                  {"bloat_fraction", errors[i].bloatFraction}};
    report["output"] = folder.string();
    std::cout << report.dump(2) << "\n";
    return;
  }
  printSummary(loaded);
  std::printf("surfelize  %s nodes above %s triangles share %s arrays: %s surfels in %.1f s (capture %u px)\n",
              withThousands(stats.nodesWithSurfels).c_str(), withThousands(settings.file.threshold).c_str(),
              withThousands(stats.arrays).c_str(), withThousands(stats.surfels).c_str(), surfelizeSeconds,
              settings.file.resolution);
  std::printf(
      "render     %ux%u against Embree at %u samples per pixel (%.1f s); each time the median of %d draws, FLIP "
      "over the foreground (lower is better):\n",
      options.width, options.height, kReferenceSamples, reference.seconds, kTimedFrames);
  for (std::size_t i = 0; i < std::size(frames); ++i)
    std::printf("  %-18s %8.1f ms   FLIP %.4f   foreground PSNR %5.1f dB   holes %.3f   bloat %.3f\n", frames[i].name,
                frames[i].frame.seconds * 1e3, errors[i].flipForegroundMean, errors[i].foregroundPsnr,
                errors[i].holeFraction, errors[i].bloatFraction);
  std::printf("  surfels draw %s surfels and %s triangles, %.1fx the speed of one ray per pixel\n",
              withThousands(fast.stats.surfels).c_str(), withThousands(fast.stats.triangles).c_str(), speedup);
  std::printf("wrote      %s/{default.surfels, surfels.png, embree.png, reference.png}\n", folder.string().c_str());
}

}  // namespace

void addDemoCommand(CLI::App& app) {
  auto options = std::make_shared<DemoOptions>();
  // The demo captures at 256 px (surfelize's default is 512): a quarter of the work, so the whole
  // pipeline runs in well under a minute on two cores.
  options->surfelize.file.resolution = 256;
  SurfelFileOptions& file = options->surfelize.file;
  CLI::App* command = app.add_subcommand(
      "demo",
      "The main job on the embedded default scene (or SCENE): surfelize, render with surfels and with rays, "
      "measure both against a converged reference");
  command->add_option("scene", options->scene, "a .gltf/.glb file, or 'default'")->capture_default_str();
  command->add_option("-o,--output", options->output, "folder for the .surfels file and the three images")
      ->capture_default_str();
  addMinTrianglesOption(*command, file.threshold);
  addOctreeOptions(*command, options->octree);
  command->add_option("--max-surfels", file.maxSurfels, "surfels per array at most")
      ->check(CLI::Range(1u, 1u << 26))
      ->capture_default_str();
  addCaptureOptions(*command, file.resolution, file.directions);
  command->add_option("--width", options->width, "image width")
      ->check(CLI::Range(1u, kMaxViewportSize))
      ->capture_default_str();
  command->add_option("--height", options->height, "image height")
      ->check(CLI::Range(1u, kMaxViewportSize))
      ->capture_default_str();
  command->add_flag("--json", options->json, "print JSON instead of text");
  addThreadsOption(*command, options->threads);
  command->callback([options] { runWithThreads(options->threads, [&] { run(*options); }); });
}

}  // namespace pbs::cli
