// `pbs eval SCENE --surfels F -o DIR`: error against run time. A camera path rendered once as the
// converged reference (Embree at many samples per pixel), then the peers (the exact renderers a user
// already has), the surfels and every setting of a sweep over the same views, timed and compared with
// it; written as DIR/eval.csv, DIR/summary.json, DIR/error_vs_time.svg and DIR/contact_sheet.png.
// Simplified meshes (simplify=R) are measured the same way, as the alternative to surfels.
#include "commands.hpp"
#include <pbs/evaluation/eval_outputs.hpp>
#include <pbs/evaluation/eval_run.hpp>
#include <pbs/evaluation/eval_settings.hpp>
#include <pbs/evaluation/eval_sources.hpp>
#include "image_files.hpp"
#include "orbit_views.hpp"
#include "progress_meter.hpp"
#include <pbs/evaluation/report_numbers.hpp>
#include "scene_report.hpp"
#include <pbs/evaluation/svg_plot.hpp>

#include <pbs/raster/flip.hpp>
#include <pbs/raster/thread_arena.hpp>
#include <pbs/scene/lazy_meshes.hpp>
#include <pbs/scene/simplified_meshes.hpp>
#include <pbs/surfels/surfel_cache.hpp>
#include <pbs/surfels/surfel_file.hpp>
#include <pbs/surfels/surfelize.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>

namespace pbs::cli {
namespace {

struct EvalOptions {
  std::string scene;
  std::string surfels;
  std::string output;
  std::vector<std::string> sweeps;
  std::vector<std::string> peers = defaultPeers();
  std::string path = "orbit";
  std::uint32_t referenceSamples = 64;
  TextureFiltering textures = TextureFiltering::Anisotropic;  // the settings' frames; not the reference's
  glm::vec3 background{1.0f};
  double pixelsPerDegree = kDefaultPixelsPerDegree;
  std::uint32_t frames = 24;
  int draws = 3;
  std::string size = "1920x1080";
  std::string orbit = "30,20,2.5";
  std::string referenceRenderer = "embree";
  LodOptions baseline;  // what every setting starts from
  CaptureSource captureFrom = CaptureSource::Auto;
  bool quiet = false;
  std::uint64_t cacheMb = 1024;
  int threads = 0;
};

void printTable(const std::vector<EvalSummary>& summaries) {
  std::printf("%-18s %6s %9s %9s %12s %12s %15s %13s %7s %8s %8s\n", "setting", "frames", "median ms", "speed-up",
              "surfels", "triangles", "FLIP med/worst", "fg PSNR med", "SSIM", "holes", "bloat");
  for (const EvalSummary& s : summaries) {
    char flip[32];
    std::snprintf(flip, sizeof flip, "%.4f/%.4f", s.medianFlip, s.worstFlip);
    std::printf("%-18s %6zu %9.2f %8.2fx %12s %12s %15s %13s %7.4f %8.4f %8.4f\n", s.name.c_str(), s.frames,
                s.medianSeconds * 1e3, s.medianSpeedup, withThousands(std::uint64_t(s.medianSurfels)).c_str(),
                withThousands(std::uint64_t(s.medianTriangles)).c_str(), flip,
                decibelText(s.medianForegroundPsnr).c_str(), s.medianSsim, s.medianHoleFraction, s.medianBloatFraction);
  }
}

void run(const EvalOptions& options) {
  const Orbit orbit = parseOrbit(options.orbit);
  const auto [width, height] = parseSize(options.size);
  const RenderMode referenceMode = *renderModeFromName(options.referenceRenderer);
  const auto surfelsStart = std::chrono::steady_clock::now();
  SurfelFileReader reader(options.surfels);  // its tables: what the arrays were made with
  double surfelsLoadSeconds = secondsSince(surfelsStart);
  const SurfelOrdering fileOrdering = reader.options().ordering;
  const LodOptions& baseline = options.baseline;
  std::vector<EvalSetting> settings;
  try {
    settings =
        evalSettings(options.peers, options.sweeps.empty() ? defaultSweep(fileOrdering) : options.sweeps, baseline);
  } catch (const SweepError& error) {
    throw CLI::ValidationError(error.option(), error.what());
  }
  const std::size_t baselineIndex = baselineSetting(settings);

  // A glTF scene whose file can check it without its meshes (drawableWithoutMeshes) is opened so where
  // nothing needs them all: a scene larger than memory is measured against the rasterizer's reference,
  // drawn node by node.
  const bool meshesOnDemand =
      drawableWithoutMeshes(options.scene, reader) && drawableWithMeshesOnDemand(settings, referenceMode, fileOrdering);
  const std::uint64_t cacheBytes = options.cacheMb << 20;
  const auto loadStart = std::chrono::steady_clock::now();
  const SceneFit fit{.rays = castsRaysOverWholeScene(settings, referenceMode)};
  LoadedScene loaded = meshesOnDemand ? openWithoutMeshes(options.scene, reader)
                                      : loadAndAnalyze(options.scene, LoadOptions{}, reader, fit);
  const double loadSeconds = secondsSince(loadStart);
  std::optional<LazyMeshes> meshes;  // given the file's fingerprints before the cache takes the reader
  if (meshesOnDemand)
    meshes.emplace(loaded.scene, loaded.decodeMesh, reader.sceneTable().meshes, loaded.name, cacheBytes);
  const auto cacheStart = std::chrono::steady_clock::now();
  const ProgressEvents progress = progressMeters(options.quiet);
  EvalSurfelSources sources(loaded.scene, loaded.hierarchy, std::move(reader), cacheBytes, options.captureFrom,
                            progress);
  surfelsLoadSeconds += secondsSince(cacheStart);
  // Arrays of other orderings and simplified meshes are made before timing starts, so no frame waits on them.
  EvalSimplifiedScenes simplifiedScenes(loaded.scene, progress);
  for (const EvalSetting& setting : settings) {
    if (!setting.isPeer()) sources.of(setting);
    if (setting.simplify) simplifiedScenes.of(setting);
  }

  std::vector<Camera> cameras;
  for (const PathView& view : pathViews(loaded, options.path, orbit, options.frames, width, height))
    cameras.push_back(view.camera);
  const auto surfelsOf = [&](const EvalSetting& s) { return sources.of(s); };
  const EvalInputs inputs{.referenceMode = referenceMode,
                          .referenceSamples = options.referenceSamples,
                          .textures = options.textures,
                          .meshes = meshes ? &*meshes : nullptr,
                          .compare = {.background = options.background, .pixelsPerDegree = options.pixelsPerDegree},
                          .sheetFrame = std::uint32_t(cameras.size() / 2),
                          .draws = options.draws,
                          .kindSurfels = &sources.decisions(),
                          .kindLod = baseline};
  ProgressMeter meter("eval", ProgressMeter::styleFor(options.quiet));
  const EvalResults results = runEval(
      loaded.scene, loaded.hierarchy, cameras, settings, inputs, surfelsOf,
      [&](const EvalSetting& s) -> const Scene& { return simplifiedScenes.of(s); },
      [&](std::size_t done, std::size_t total, const std::string& detail) {
        meter.update(double(done) / double(total), detail);
      });
  meter.finish(std::to_string(settings.size()) + " settings × " + std::to_string(cameras.size()) + " frames");

  const EvalRunInfo info{.scene = loaded.name,
                         .surfels = options.surfels,
                         .path = options.path,
                         .width = width,
                         .height = height,
                         .frames = std::uint32_t(cameras.size()),
                         .referenceRenderer = options.referenceRenderer,
                         .referenceSamples = options.referenceSamples,
                         .meshesOnDemand = meshesOnDemand,
                         .baseline = baselineIndex,
                         .loadSeconds = loadSeconds,
                         .surfelsLoadSeconds = surfelsLoadSeconds,
                         .surfelBytesRead = sources.bytesRead()};
  EvalFiles files = evalFiles(info, settings, results, inputs.sheetFrame, options.background);
  files.summary["simplification"] = simplifiedScenes.json();
  files.summary["texture_filter"] = textureFilteringName(options.textures);
  files.summary["draws_per_frame"] = options.draws;
  const std::filesystem::path folder(options.output);
  std::filesystem::create_directories(folder);
  writeTextFile(folder / "eval.csv", files.csv);
  writeTextFile(folder / "error_vs_time.svg", files.plot);
  writeImage8(folder / "contact_sheet.png", files.sheetWidth, files.sheetHeight, 3, files.sheet);
  writeTextFile(folder / "summary.json", files.summary.dump(2) + "\n");

  std::printf("%s, %s path: %ux%u, %zu frames; reference %s at %u samples, median %.1f ms; BVH %.2f s, load %.2f s%s\n",
              loaded.name.c_str(), options.path.c_str(), width, height, cameras.size(),
              options.referenceRenderer.c_str(), options.referenceSamples,
              files.summary["reference"]["median_seconds"].get<double>() * 1e3, results.buildSeconds, loadSeconds,
              meshesOnDemand ? "; meshes read as frames draw them" : "");
  std::string kinds;
  for (FrameKind kind : {FrameKind::Near, FrameKind::Mid, FrameKind::Far}) {
    const auto n =
        std::count_if(results.views.begin(), results.views.end(), [&](const EvalView& v) { return v.kind == kind; });
    kinds += std::string(kinds.empty() ? "" : ", ") + std::to_string(n) + " " + frameKindName(kind);
  }
  std::printf("frames: %s\n", kinds.c_str());
  printTable(files.summaries);
  std::printf("wrote %s/{eval.csv, summary.json, error_vs_time.svg, contact_sheet.png}\n", folder.string().c_str());
}

}  // namespace

void addEvalCommand(CLI::App& app) {
  auto options = std::make_shared<EvalOptions>();
  CLI::App* command = app.add_subcommand(
      "eval",
      "Error against run time: the peers (Embree rays at 1, 4, 16 samples per pixel, the rasterizer at 1), surfels "
      "and a sweep of LOD settings over a camera path, every frame compared with a converged reference (Embree at "
      "--reference-samples): FLIP and PSNR over the foreground, SSIM, holes, bloat, time");
  command->add_option("scene", options->scene, "a .gltf/.glb file, or 'default'")->required();
  command->add_option("--surfels", options->surfels, "the scene's .surfels file (from pbs surfelize)")->required();
  command
      ->add_option("-o,--output", options->output,
                   "folder for eval.csv, summary.json, error_vs_time.svg, contact_sheet.png (created if missing)")
      ->required();
  command->add_option(
      "--sweep", options->sweeps,
      "KEY=V1,V2,… or KEY=V+KEY=V (keys: " + sweepKeys() +
          "), repeatable; each value one setting over the baseline LOD options (--threshold-pixels, --point-size, "
          "…), which is measured as 'surfels'. Default: "
          "overdraw=4,8,32 threshold=64,256 splat=nearest, the file's other orderings and "
          "simplify=0.25,0.05,0.01 (meshes simplified to that fraction of their triangles, drawn in "
          "place of surfels)");
  command
      ->add_option("--peers", options->peers,
                   "the exact renderers measured beside the surfels: embree=N,… (rays, N samples per pixel) and "
                   "exact=N,… (the rasterizer drawing every triangle)")
      ->capture_default_str();
  addLodOptions(*command, options->baseline);
  addPathOption(*command, options->path);
  addSamplesOption(*command, "--reference-samples", options->referenceSamples,
                   "samples per pixel of the reference every frame is compared with");
  addTextureFilterOption(*command, options->textures);
  command
      ->add_option(
          "--reference", options->referenceRenderer,
          "what draws the reference: embree (rays) or exact (the rasterizer; for a glTF scene with a "
          ".surfels file of version 4 or later and no Embree peer, its meshes are read as frames draw them, node by "
          "node, so a scene larger than memory, or than rays can hold, can be measured)")
      ->check(CLI::IsMember({"embree", "exact"}))
      ->capture_default_str();
  command->add_option("--frames", options->frames, "views on the path")
      ->check(CLI::Range(1u, 100000u))
      ->capture_default_str();
  command
      ->add_option("--draws", options->draws,
                   "draws of each view by each setting (not the reference): the first gives the image, the median "
                   "time the frame's time")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  command->add_option("--size", options->size, "WxH pixels")->capture_default_str();
  command
      ->add_option("--orbit", options->orbit,
                   "AZ,EL,DIST: degrees, degrees, distance in bounding radii (the orbit; the approach's direction "
                   "and start)")
      ->capture_default_str();
  addCompareOptions(*command, options->background, options->pixelsPerDegree);
  addCaptureSourceOption(*command, options->captureFrom,
                         "how arrays of other orderings are made on demand (the .surfels file does not record it: "
                         "give what it was made with)");
  command->add_flag("-q,--quiet", options->quiet, "no progress on stderr");
  addCacheOption(*command, options->cacheMb,
                 "the .surfels file is read as frames draw it, one cache for every setting that draws its arrays; "
                 "the arrays drawn longest ago are dropped beyond this many MB");
  addThreadsOption(*command, options->threads);
  command->callback([options] { runWithThreads(options->threads, [&] { run(*options); }); });
}

}  // namespace pbs::cli
