// `pbs render SCENE [--surfels F] [--mode surfels|exact|embree]`: one view (or the frames of a camera
// path) of a scene with surfels for small nodes, or exactly with the rasterizer or the ray caster
// (paper, Sec. 3), at one or many samples per pixel.
#include "commands.hpp"
#include "frame_scene.hpp"
#include "image_files.hpp"
#include "memory_limit.hpp"
#include <pbs/evaluation/report_numbers.hpp>
#include "orbit_views.hpp"
#include "scene_report.hpp"
#include "shard_option.hpp"

#include <pbs/raster/headlight_shading.hpp>
#include <pbs/raster/thread_arena.hpp>
#include <pbs/scene/input_error.hpp>
#include <pbs/surfels/frame_cost.hpp>
#include <pbs/surfels/frame_renderer.hpp>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>

namespace pbs::cli {
namespace {

struct RenderOptions {
  std::string scene;
  std::string surfels;
  std::string mode;  // empty: surfels when a file is given, else exact
  std::string orbit = "30,20,2.5";
  std::string path = "orbit";
  std::string size = "1920x1080";
  LodOptions lod;
  std::string output;
  std::uint32_t frames = 0;
  bool budgetFeedback = false;
  std::uint32_t samples = 1;
  TextureFiltering textures = TextureFiltering::Anisotropic;
  bool json = false;
  std::uint64_t maxMemory = 0;
  std::uint64_t cacheMb = 1024;
  double streamMBps = 0.0;  // 0: read from the file as frames need it
  double streamFps = 30.0;
  std::string streamOrder = "prefixes";
  std::optional<ShardChoice> shard;
  int threads = 0;
};

// Whether frame f is this run's: with --shard I/N, the frames f with f mod N = I (neighbouring frames of
// a path cost about the same, so taking every N-th balances the shards better than blocks would).
bool rendersFrame(const RenderOptions& options, std::uint32_t f) {
  return !options.shard || f % options.shard->count == options.shard->index;
}

// Where frame f goes: the -o file itself for one view, else frame_NNNN.png in the -o folder.
std::filesystem::path frameFile(const RenderOptions& options, std::uint32_t f) {
  const std::filesystem::path output(options.output);
  if (options.frames == 0) return output;
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04u.png", f);
  return output / name;
}

// An EXR keeps the shaded float image; any other format gets its 8-bit conversion.
bool keepsFloat(const std::filesystem::path& file) { return file.extension() == ".exr"; }

// What the frames make of their G-buffer: nothing without -o, else what the file keeps.
FrameImage frameImage(const RenderOptions& options) {
  if (options.output.empty()) return FrameImage::None;
  return keepsFloat(frameFile(options, 0)) ? FrameImage::Float : FrameImage::Rgba8;
}

void writeFrame(const std::filesystem::path& file, std::uint32_t width, std::uint32_t height,
                const FrameResult& frame) {
  if (keepsFloat(file))
    writeImageFloat(file, width, height, 4, std::span(&frame.image.front().x, frame.image.size() * 4));
  else
    writeImage8(file, width, height, 4, frame.rgba8);
}

nlohmann::json frameJson(RenderMode mode, const FrameResult& frame) {
  nlohmann::json entry = {{"seconds", frame.seconds},
                          {"traverse_seconds", frame.stats.traverseSeconds},
                          {"raster_seconds", frame.stats.rasterSeconds},
                          {"triangles", frame.stats.triangles},
                          {"surfels", frame.stats.surfels},
                          {"nodes_geometry", frame.stats.nodesGeometry},
                          {"nodes_surfels", frame.stats.nodesSurfels}};
  if (mode == RenderMode::Surfels) {
    entry["geometry"] = geometryDrawerName(frame.stats.geometryDrawer);
    entry["surfel_load_seconds"] = frame.surfelLoadSeconds;
    entry["geometry_seconds"] = frame.stats.geometrySeconds;
    entry["bvh_build_seconds"] = frame.stats.bvhBuildSeconds;
    entry["geometry_pixels"] = frame.stats.geometryPixels;
    entry["geometry_ray_pixels"] = frame.stats.geometryRayPixels;
    entry["triangles_on_pixels"] = frame.stats.trianglesOnPixels;
    entry["surfel_pixels"] = frame.stats.surfelPixels;
    entry["resolution_divisor"] = frame.divisor;
  }
  return entry;
}

nlohmann::json streamJson(const StreamStats& stream) {
  return {{"stream_seconds", stream.seconds},
          {"stream_bytes", stream.bytes},
          {"stream_missing_bytes", stream.missingBytes},
          {"stream_missing_pixels", stream.missingPixels}};
}

// "; streamed 12.3 MB by 0.50 s, 4.1 MB missing": where the simulated link stands.
std::string streamText(const StreamStats& stream) {
  char text[96];
  std::snprintf(text, sizeof text, "; streamed %.1f MB by %.2f s, %.1f MB missing", stream.bytes / 1e6, stream.seconds,
                stream.missingBytes / 1e6);
  return text;
}

// "; geometry by rays 3.1 ms (BVH builds 1.2)": how the geometry nodes were drawn, in surfels mode.
std::string geometryText(RenderMode mode, const LodStats& stats) {
  if (mode != RenderMode::Surfels) return "";
  char text[96];
  std::snprintf(text, sizeof text, "; geometry by %s %.1f ms (BVH builds %.1f)",
                geometryDrawerName(stats.geometryDrawer), stats.geometrySeconds * 1e3, stats.bvhBuildSeconds * 1e3);
  return text;
}

void run(const RenderOptions& options) {
  std::optional<ImagePluginPreload> preload;
  if (!options.output.empty() && !writesWithoutPlugin(frameFile(options, 0))) preload.emplace();
  const Orbit orbit = parseOrbit(options.orbit);
  const auto [width, height] = parseSize(options.size);
  const std::string modeName = !options.mode.empty() ? options.mode : options.surfels.empty() ? "exact" : "surfels";
  // A shard's frames must not depend on the frames other shards render.
  if (options.shard && options.frames == 0) throw CLI::ValidationError("--shard", "shares frames out: give --frames N");
  if (options.shard && (options.streamMBps > 0.0 || options.budgetFeedback))
    throw CLI::ValidationError("--shard", std::string("not with ") +
                                              (options.streamMBps > 0.0 ? "--stream" : "--budget-feedback") +
                                              ", whose frames depend on every frame before them");
  const RenderMode mode = *renderModeFromName(modeName);
  if (mode == RenderMode::Surfels && options.surfels.empty())
    throw CLI::ValidationError("--mode surfels", "needs --surfels FILE (make one with pbs surfelize)");
  // Per pixel: the G-buffer (depth, colour, normal), the shaded image and its 8-bit copy, the sums of
  // a supersampled frame; the surfels and the meshes read on demand come on top, each up to the cache's
  // budget. A stream simulates its own link for meshes, so it reads them whole.
  const std::uint64_t pixelBytes =
      std::uint64_t(width) * height * (4 + 4 + 12 + 16 + 4 + (options.samples > 1 ? 16 : 0));
  FrameScene opened({.scene = options.scene,
                     .surfels = mode == RenderMode::Surfels ? options.surfels : "",
                     .cacheBytes = options.cacheMb << 20,
                     .meshesOnDemand = options.streamMBps <= 0.0,
                     .rays = mode == RenderMode::Embree,
                     .alongside = pixelBytes,
                     .what = "rendering " + std::to_string(width) + "x" + std::to_string(height),
                     .maxMemory = options.maxMemory});
  const LoadedScene& loaded = opened.loaded;
  std::optional<LazyMeshes>& meshes = opened.meshes;
  std::optional<SurfelCache>& surfels = opened.surfels;
  const std::uint64_t bvhEstimate =
      mode == RenderMode::Embree ? embreeMemoryEstimate(loaded.scene, loaded.hierarchy) : 0;
  if (mode == RenderMode::Embree) {
    // The rays' BVHs come on top of the scene: refuse a build that would not fit before starting it.
    std::uint64_t sceneBytes = 0;
    for (const Mesh& mesh : loaded.scene.meshes) sceneBytes += meshBytes(mesh);
    requireMemory(opened.foreseenBytes + sceneBytes + bvhEstimate,
                  "ray casting " + loaded.name + " (" + withThousands(loaded.summary.uniqueTriangles) +
                      " triangles in Embree's BVHs)",
                  options.maxMemory);
  }
  if (options.streamMBps > 0.0 && !surfels)
    throw CLI::ValidationError("--stream", options.surfels.empty() ? "streams a .surfels file: give --surfels FILE"
                                                                   : "streams surfels: not with --mode " + modeName);
  std::optional<SurfelStream> stream;
  if (options.streamMBps > 0.0)
    stream.emplace(
        *surfels, loaded.scene, loaded.hierarchy, options.lod,
        StreamOptions{.bytesPerSecond = options.streamMBps * 1e6, .order = *streamOrderFromName(options.streamOrder)});
  const std::vector<PathView> views = pathViews(loaded, options.path, orbit, options.frames, width, height);
  const std::uint32_t frames = std::uint32_t(views.size());
  // The path's frames share the mesh BVHs that rays build: each is charged its share of a build. All of them,
  // not only this shard's, so that a shard prices a build as the unsharded run does.
  LodOptions lod = options.lod;
  lod.bvhBuildFrames = double(frames);
  const FrameImage image = frameImage(options);
  FrameRenderer renderer(
      loaded.scene, loaded.hierarchy,
      {.mode = mode, .lod = lod, .samples = options.samples, .image = image, .textures = options.textures}, width,
      height,
      {.cache = surfels ? &*surfels : nullptr,
       .stream = stream ? &*stream : nullptr,
       .meshes = meshes ? &*meshes : nullptr});
  const std::filesystem::path output(options.output);
  if (options.frames > 0 && !output.empty()) std::filesystem::create_directories(output);

  nlohmann::json report = {
      {"scene", loaded.name}, {"mode", modeName}, {"width", width}, {"height", height}, {"samples", options.samples}};
  // What the frames use, so that a user can see what was left out (a channel no pass reads is never
  // allocated, and the 8-bit conversion runs only for an 8-bit image file).
  report["used"] = {
      {"gbuffer", channelNames(renderer.channels())},
      {"cleared_each_pass", renderer.clearsDepth() ? std::vector<std::string>{"depth"} : std::vector<std::string>{}},
      {"passes_per_frame", options.samples},
      {"texture_filter", textureFilteringName(options.textures)},
      // Frames shade only what the file keeps: the float image, the 8-bit one directly, or nothing.
      {"image_file", image == FrameImage::None    ? "none"
                     : image == FrameImage::Float ? "float"
                                                  : "8-bit"}};
  if (mode == RenderMode::Embree) {
    report["build_seconds"] = renderer.buildSeconds();
    report["bvh_peak_bytes"] = renderer.bvhPeakBytes();
    report["bvh_estimate_bytes"] = bvhEstimate;
  }
  report["used"]["meshes"] = meshes ? "read as frames draw them" : "read whole";
  std::vector<double> seconds;
  const bool timeBudget =
      mode == RenderMode::Surfels && options.lod.budget.unit == BudgetUnit::Seconds && options.lod.budget.limit > 0.0;
  if (options.budgetFeedback && !timeBudget)
    throw CLI::ValidationError("--budget-feedback", "corrects --budget-ms: give it, in surfels mode");
  BudgetFeedback feedback(options.lod.budget.limit);
  std::uint32_t end = frames;  // after this run's last frame
  while (end > 0 && !rendersFrame(options, end - 1)) --end;
  for (std::uint32_t f = 0; f < end; ++f) {
    if (!rendersFrame(options, f)) {
      // Another shard's frame, passed over so that this run's frames see what they would had the run drawn it.
      renderer.passOver(views[f].camera);
      continue;
    }
    // Frame f shows what the link delivered by (f + 1) / fps.
    if (stream) stream->advance(views[f].camera, 1.0 / options.streamFps);
    const double limit = feedback.limit();
    if (options.budgetFeedback) {
      LodBudget corrected = options.lod.budget;
      corrected.limit = limit;
      renderer.setBudget(corrected);
    }
    const FrameResult frame = renderer.render(views[f].camera);
    seconds.push_back(frame.seconds);
    nlohmann::json entry = frameJson(mode, frame);
    if (timeBudget) {
      const double predicted =
          predictFrameCost(options.lod.frameCosts,
                           frameWork(frame.stats, std::uint64_t(frame.drawnWidth) * frame.drawnHeight),
                           frame.stats.geometryDrawer) +
          (frame.divisor > 1.0 ? predictUpscaleCost(options.lod.frameCosts, double(width) * height) : 0.0);
      feedback.observe(predicted, frame.recurringSeconds());
      entry["budget_limit_seconds"] = options.budgetFeedback ? limit : options.lod.budget.limit;
      entry["predicted_seconds"] = predicted;
    }
    if (stream) entry.update(streamJson(stream->stats()));
    if (!output.empty()) {
      const std::filesystem::path file = frameFile(options, f);
      writeFrame(file, width, height, frame);
      entry["file"] = file.string();
    }
    if (options.frames > 0) {
      report["frames"].push_back(entry);
      if (!options.json)
        std::printf("frame %u: %.1f ms (traverse %.1f, raster %.1f), %s triangles, %s surfels%s%s\n", f,
                    frame.seconds * 1e3, frame.stats.traverseSeconds * 1e3, frame.stats.rasterSeconds * 1e3,
                    withThousands(frame.stats.triangles).c_str(), withThousands(frame.stats.surfels).c_str(),
                    geometryText(mode, frame.stats).c_str(), stream ? streamText(stream->stats()).c_str() : "");
    } else {
      report.update(entry);
      if (!options.json)
        std::printf(
            "%s, %s: %ux%u in %.1f ms (traverse %.1f, raster %.1f): %s triangles of %s nodes, %s surfels of "
            "%s nodes%s%s%s%s\n",
            loaded.name.c_str(), modeName.c_str(), width, height, frame.seconds * 1e3,
            frame.stats.traverseSeconds * 1e3, frame.stats.rasterSeconds * 1e3,
            withThousands(frame.stats.triangles).c_str(), withThousands(frame.stats.nodesGeometry).c_str(),
            withThousands(frame.stats.surfels).c_str(), withThousands(frame.stats.nodesSurfels).c_str(),
            geometryText(mode, frame.stats).c_str(), stream ? streamText(stream->stats()).c_str() : "",
            output.empty() ? "" : "; wrote ", output.string().c_str());
    }
  }
  if (options.frames > 0) {
    const double medianSeconds = median(seconds);
    report["median_seconds"] = medianSeconds;
    if (options.shard) report["shard"] = {{"index", options.shard->index}, {"count", options.shard->count}};
    if (!options.json)
      std::printf("%zu frames%s: median %.1f ms\n", seconds.size(),
                  options.shard ? (" of " + std::to_string(frames)).c_str() : "", medianSeconds * 1e3);
  }
  if (surfels) {
    report["surfel_bytes_read"] = surfels->stats().bytesRead;
    report["surfel_peak_bytes_loaded"] = surfels->stats().peakBytesLoaded;
  }
  if (meshes) {
    const LazyMeshStats read = meshes->stats();
    report["meshes_decoded"] = read.decoded;
    report["mesh_peak_bytes_loaded"] = read.peakBytesLoaded;
    report["mesh_decode_seconds"] = read.decodeSeconds;
    if (!options.json)
      std::printf("meshes read as frames drew them: %s decoded of %s (peak %.1f MB)\n",
                  withThousands(read.decoded).c_str(), withThousands(loaded.scene.meshes.size()).c_str(),
                  read.peakBytesLoaded / 1e6);
  }
  if (options.json) std::cout << report.dump(2) << "\n";
}

}  // namespace

void addRenderCommand(CLI::App& app) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* command = app.add_subcommand(
      "render", "Render a view (or a camera path) with surfels for small nodes, or exactly (rasterizer or rays)");
  command->add_option("scene", options->scene, "a .gltf/.glb file, or 'default'")->required();
  command->add_option("--surfels", options->surfels, "the scene's .surfels file (from pbs surfelize)");
  command->add_option("--mode", options->mode, "surfels (default with --surfels), exact (rasterizer) or embree (rays)")
      ->check(CLI::IsMember({"surfels", "exact", "embree"}));
  addSamplesOption(*command, "--samples", options->samples,
                   "samples per pixel, resolved into colour with fractional alpha (coverage)");
  addTextureFilterOption(*command, options->textures);
  command
      ->add_option("--orbit", options->orbit,
                   "AZ,EL,DIST: degrees, degrees, distance in bounding radii (the orbit; the approach's direction "
                   "and start)")
      ->capture_default_str();
  addPathOption(*command, options->path);
  command->add_option("--size", options->size, "WxH pixels")->capture_default_str();
  addLodOptions(*command, options->lod);
  command->add_option("-o,--output", options->output, "image (.png or .exr); with --frames a folder of PNGs");
  command->add_option("--frames", options->frames, "render N frames along the --path (default: one view, its first)")
      ->check(CLI::Range(1u, 100000u));
  command->add_flag("--json", options->json, "print JSON (per-frame figures with --frames)");
  command->add_flag("--budget-feedback", options->budgetFeedback,
                    "with --budget-ms and --frames: lower the limit where the last frames took longer than predicted "
                    "(frames then depend on timing)");
  addCacheOption(
      *command, options->cacheMb,
      "surfels (and, for a glTF scene with a .surfels file of version 4 or later, meshes) are read as frames draw "
      "them; the least recently drawn arrays and meshes are dropped beyond this many MB each");
  command
      ->add_option("--stream", options->streamMBps,
                   "MB/s: as if the .surfels file and the meshes came over a link of this many megabytes (10^6 "
                   "bytes) a second; each frame draws what has arrived (prefixes cut short, geometry only where "
                   "its mesh arrived), the link fetching what the view lacks most first")
      ->check(positiveNumber());
  command
      ->add_option("--stream-fps", options->streamFps,
                   "frames a second on the stream's clock: frame f shows what arrived by (f + 1) / fps")
      ->check(positiveNumber())
      ->capture_default_str();
  command
      ->add_option("--stream-order", options->streamOrder,
                   "prefixes: a chunk at a time of the prefix that lacks most pixels; arrays: whole arrays one by "
                   "one, each drawn once complete")
      ->check(CLI::IsMember({"prefixes", "arrays"}))
      ->capture_default_str();
  addShardOption(*command, options->shard,
                 "with --frames: render only the frames f with f mod N = I, into the same folder under the same "
                 "names");
  addMaxMemoryOption(*command, options->maxMemory);
  addThreadsOption(*command, options->threads);
  command->callback([options] { runWithThreads(options->threads, [&] { run(*options); }); });
}

}  // namespace pbs::cli
