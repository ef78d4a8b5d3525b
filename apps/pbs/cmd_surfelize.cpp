// `pbs surfelize SCENE -o OUT.surfels`: ordered surfel arrays for every complex node of a scene,
// shared between instances, written as one .surfels file (paper, Sec. 2).
#include "commands.hpp"
#include "memory_limit.hpp"
#include "progress_meter.hpp"
#include <pbs/evaluation/report_numbers.hpp>
#include "scene_report.hpp"
#include "shard_option.hpp"

#include <pbs/raster/thread_arena.hpp>
#include <pbs/surfels/capture.hpp>
#include <pbs/surfels/surfelize.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>

namespace pbs::cli {
namespace {

// What reading a glTF's meshes as captures draw them holds besides the captures: the cache's budget and
// up to two meshes a worker in the scan.
std::uint64_t lazyMeshMemory(const Scene& scene, std::uint64_t cacheBytes, int workers) {
  std::uint64_t largest = 0;
  for (const Mesh& mesh : scene.meshes) largest = std::max(largest, foreseenMeshBytes(mesh));
  return cacheBytes + 2 * std::uint64_t(std::max(workers, 1)) * largest;
}

std::string progressDetail(const SurfelizeProgress& p) {
  return std::to_string(p.arraysDone) + "/" + std::to_string(p.arraysTotal) + " arrays, " + withThousands(p.surfels) +
         " surfels";
}

// `--shard-plan N`: per shard, the arrays held and made and the estimated seconds, and how far the
// slowest shard is from an even split.
void printShardPlan(const LoadedScene& loaded, const SurfelizeOptions& settings, std::uint32_t count, bool json) {
  const std::vector<SurfelizeShardEstimate> shards =
      planSurfelizeShards(loaded.scene, loaded.hierarchy, settings, count);
  double slowest = 0.0;
  for (const SurfelizeShardEstimate& shard : shards) slowest = std::max(slowest, shard.estimatedSeconds);
  const SurfelizeShardEstimate whole = planSurfelizeShards(loaded.scene, loaded.hierarchy, settings, 1).front();
  const double total = whole.estimatedSeconds;
  if (json) {
    nlohmann::json report = {{"scene", loaded.name}, {"shards", count}, {"estimated_seconds_one_shard", total}};
    for (const SurfelizeShardEstimate& shard : shards)
      report["per_shard"].push_back({{"arrays_held", shard.arraysHeld},
                                     {"arrays_made", shard.arraysMade},
                                     {"estimated_seconds", shard.estimatedSeconds}});
    std::cout << report.dump(2) << "\n";
    return;
  }
  std::printf("%s: %s arrays over %u shards (estimated seconds on one core; one shard: %.1f s)\n", loaded.name.c_str(),
              withThousands(whole.arraysHeld).c_str(), count, total);
  for (std::uint32_t s = 0; s < count; ++s)
    std::printf("shard %u/%u: holds %s arrays, makes %s, %.1f s\n", s, count,
                withThousands(shards[s].arraysHeld).c_str(), withThousands(shards[s].arraysMade).c_str(),
                shards[s].estimatedSeconds);
  std::printf("slowest shard %.1f s: %.2fx faster than one shard (%u at best)\n", slowest,
              slowest > 0.0 ? total / slowest : 1.0, count);
}

}  // namespace

void addSurfelizeCommand(CLI::App& app) {
  struct Options {
    std::string scene;
    std::string output;
    SurfelizeOptions surfelize;
    bool json = false;
    bool quiet = false;
    std::uint64_t maxMemory = 0;
    std::uint64_t cacheMb = 1024;
    OctreeChoice octree;
    std::optional<ShardChoice> shard;
    std::uint32_t shardPlan = 0;
    int threads = 0;
  };
  auto options = std::make_shared<Options>();
  SurfelFileOptions& file = options->surfelize.file;
  CLI::App* command = app.add_subcommand("surfelize", "Make ordered surfel arrays for every complex node of a scene");
  command->add_option("scene", options->scene, "a .gltf/.glb file, or 'default' for the embedded scene")->required();
  command->add_option("-o,--output", options->output, "the .surfels file to write")->required();
  addMinTrianglesOption(*command, file.threshold);
  addOctreeOptions(*command, options->octree);
  command->add_option("--max-surfels", file.maxSurfels, "surfels per array at most")
      ->check(CLI::Range(1u, 1u << 26))
      ->capture_default_str();
  addCaptureOptions(*command, file.resolution, file.directions);
  addOrderingOption(*command, file.ordering);
  std::map<std::string, SurfelColors> colorNames;
  for (SurfelColors c : {SurfelColors::Pixel, SurfelColors::Prefiltered})
    colorNames.emplace(std::string(surfelColorsName(c)), c);
  command
      ->add_option("--colors", file.colors,
                   "surfel colours: pixel (default: the one captured pixel's) or prefiltered (each surfel's "
                   "neighbourhood averaged, as wide as its spacing in the order; measured to buy nothing, at 15 % "
                   "of surfelize's time)")
      ->transform(CLI::CheckedTransformer(colorNames));
  addCaptureSourceOption(*command, options->surfelize.source,
                         "what an inner node's capture draws: its subtree's triangles (exact) or its children's "
                         "surfels (fast)");
  command->add_option("--seed", file.seed, "seed of the orderings")->capture_default_str();
  addShardOption(*command, options->shard,
                 "write only the arrays of shard I of N (a part, which pbs merge puts together with the others "
                 "into the whole file), shards balanced by estimated cost");
  command
      ->add_option("--shard-plan", options->shardPlan,
                   "print how N shards would split the arrays (held, made, estimated seconds each) and exit: "
                   "nothing is captured, -o is not written")
      ->check(CLI::Range(1u, 1u << 20));
  command->add_flag("--json", options->json, "print JSON instead of text");
  command->add_flag("-q,--quiet", options->quiet, "no progress on stderr");
  addCacheOption(*command, options->cacheMb,
                 "a glTF scene's meshes are read as the captures draw them; those no capture is drawing are "
                 "dropped, least recently used first, beyond this many MB");
  addMaxMemoryOption(*command, options->maxMemory);
  addThreadsOption(*command, options->threads);
  command->callback([options] {
    runWithThreads(options->threads, [&] {
      const auto start = std::chrono::steady_clock::now();
      // A glTF file is opened without its mesh arrays, which are read as the captures draw them (the
      // embedded scene is made whole in memory).
      bool meshesOnDemand = options->scene != "default";
      LoadedScene loaded =
          meshesOnDemand ? openWithoutMeshes(options->scene) : loadAndAnalyze(options->scene, LoadOptions{});
      SurfelizeOptions settings = options->surfelize;
      settings.shard = options->shard;
      // A flat scene is rebuilt as a loose octree, read whole (its meshes are split), and the file says so.
      settings.file.octreeLeafTriangles = options->octree.leavesFor(loaded.scene);
      if (settings.file.octreeLeafTriangles > 0) {
        meshesOnDemand = false;
        loaded = loadAndAnalyze(options->scene, LoadOptions{settings.file.octreeLeafTriangles});
      }
      if (options->shardPlan > 0) {
        printShardPlan(loaded, settings, options->shardPlan, options->json);
        return;
      }
      const int workers = resolveThreadCount(options->threads);
      const std::uint64_t cacheBytes = options->cacheMb << 20;
      requireMemory(surfelizeMemoryEstimate(loaded.scene, loaded.hierarchy, settings, workers) +
                        (meshesOnDemand ? lazyMeshMemory(loaded.scene, cacheBytes, workers) : 0),
                    "surfelize " + loaded.name, options->maxMemory);
      ProgressMeter meter("surfelize", ProgressMeter::styleFor(options->quiet || options->json));
      settings.onProgress = [&](const SurfelizeProgress& p) {
        // Triangle captures cost about their subtree's triangles; child-surfel captures about the same each.
        const double fraction = settings.source == CaptureSource::Triangles
                                    ? double(p.trianglesDone) / double(std::max<std::uint64_t>(p.trianglesTotal, 1))
                                    : double(p.arraysDone) / double(std::max<std::uint32_t>(p.arraysTotal, 1));
        meter.update(fraction, progressDetail(p));
      };
      SurfelizeStats stats;
      if (meshesOnDemand)
        surfelizeToFile(loaded.scene, loaded.decodeMesh, cacheBytes, loaded.name, settings, options->output, &stats);
      else
        surfelizeToFile(loaded.scene, loaded.hierarchy, settings, options->output, &stats);
      if (stats.arrays > 0)
        meter.finish(std::to_string(stats.arrays) + " arrays, " + withThousands(stats.surfels) + " surfels");
      const std::uint64_t bytes = std::filesystem::file_size(options->output);
      const double seconds = secondsSince(start);
      // How the arrays store their colours, read back from the tables: what the file left out.
      std::map<std::string, std::uint64_t> encodings = {{"rgba", 0}, {"rgb", 0}, {"constant", 0}};
      const SurfelFileReader written(options->output);
      for (const SurfelArrayInfo& info : written.arrays()) ++encodings[colorEncodingName(info.colorEncoding)];

      if (options->json) {
        nlohmann::json report = {
            {"scene", loaded.name},
            {"output", options->output},
            {"nodes_with_surfels", stats.nodesWithSurfels},
            {"arrays", written.arrays().size()},
            {"captures", stats.arrays},
            {"surfels", stats.surfels},
            {"candidates", stats.candidates},
            {"seconds", seconds},
            {"load_seconds", loaded.parseSeconds + loaded.hierarchySeconds},
            {"bytes", bytes},
            {"bytes_per_surfel", stats.surfels > 0 ? double(bytes) / double(stats.surfels) : 0.0},
            {"color_encodings", encodings},
            {"meshes_decoded", stats.meshesDecoded},
            {"mesh_peak_bytes_loaded", stats.meshPeakBytesLoaded},
            {"used",
             {{"meshes", meshesOnDemand ? "read as captures draw them" : "read whole"},
              {"capture_gbuffer", channelNames(kCaptureChannels)},
              {"cleared_each_view", channelNames(kCaptureClearedChannels)},
              {"color_encodings", encodings}}},
            {"threshold", settings.file.threshold},
            {"max_surfels", settings.file.maxSurfels},
            {"resolution", settings.file.resolution},
            {"ordering", orderingName(settings.file.ordering)},
            {"colors", surfelColorsName(settings.file.colors)},
            {"capture_from", captureSourceName(settings.source)},
            {"seed", settings.file.seed},
            {"octree_leaf_triangles", settings.file.octreeLeafTriangles},
            {"arrays_written", stats.arraysWritten},
            {"estimated_seconds", stats.estimatedSeconds},
        };
        if (options->shard) report["shard"] = {{"index", options->shard->index}, {"count", options->shard->count}};
        std::cout << report.dump(2) << "\n";
        return;
      }
      if (stats.nodesWithSurfels == 0) {
        std::printf("%s: no node has more than %s triangles: no surfels needed (wrote an empty %s)\n",
                    loaded.name.c_str(), withThousands(settings.file.threshold).c_str(), options->output.c_str());
        return;
      }
      if (settings.file.octreeLeafTriangles > 0)
        std::printf("%s: rebuilt as a loose octree of %s nodes, leaves of at most %s triangles\n", loaded.name.c_str(),
                    withThousands(loaded.scene.nodes.size()).c_str(),
                    withThousands(settings.file.octreeLeafTriangles).c_str());
      std::printf("%s: %s nodes above %s triangles share %s arrays (%s captures): %s surfels from %s candidates\n",
                  loaded.name.c_str(), withThousands(stats.nodesWithSurfels).c_str(),
                  withThousands(settings.file.threshold).c_str(), withThousands(written.arrays().size()).c_str(),
                  withThousands(stats.arrays).c_str(), withThousands(stats.surfels).c_str(),
                  withThousands(stats.candidates).c_str());
      if (options->shard)
        std::printf("shard %u/%u: %s of the %s arrays are this part's (estimated %.1f s on one core for all it made)\n",
                    options->shard->index, options->shard->count, withThousands(stats.arraysWritten).c_str(),
                    withThousands(written.arrays().size()).c_str(), stats.estimatedSeconds);
      std::printf("wrote %s: %s bytes (%.2f per surfel; colours of %s arrays constant, %s RGB, %s RGBA) in %.2f s\n",
                  options->output.c_str(), withThousands(bytes).c_str(),
                  stats.surfels > 0 ? double(bytes) / double(stats.surfels) : 0.0,
                  withThousands(encodings["constant"]).c_str(), withThousands(encodings["rgb"]).c_str(),
                  withThousands(encodings["rgba"]).c_str(), seconds);
    });
  });
}

}  // namespace pbs::cli
