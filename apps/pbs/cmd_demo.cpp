// `pbs demo`: the main job on the embedded default scene. For now: generate and summarise it, count
// the nodes complex enough to get surfels, and run the surfel pipeline as far as it exists on the
// most complex one: capture from the eight box corners, then the progressive (farthest-point) order.
#include "commands.hpp"
#include "scene_report.hpp"

#include <pbs/raster/thread_arena.hpp>
#include <pbs/surfels/capture.hpp>
#include <pbs/surfels/ordering.hpp>
#include <pbs/surfels/surfel_nodes.hpp>

#include <chrono>

#include <cstdio>
#include <iostream>
#include <memory>

namespace pbs::cli {
namespace {

struct SurfelRun {
  std::uint32_t node = 0;
  CaptureResult capture;
  std::vector<std::uint32_t> order;
  double captureSeconds = 0, orderSeconds = 0;
};

// Captures the first root (in a scene with one root, its most complex node) and orders `max` surfels.
SurfelRun runSurfelPipeline(const LoadedScene& loaded, std::uint32_t max) {
  SurfelRun run;
  run.node = loaded.scene.roots.front();
  auto start = std::chrono::steady_clock::now();
  run.capture = captureNode(loaded.scene, loaded.hierarchy, run.node, CaptureOptions{});
  run.captureSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::vector<glm::vec3> positions;
  positions.reserve(run.capture.surfels.size());
  for (const Surfel& surfel : run.capture.surfels) positions.push_back(surfel.position);
  start = std::chrono::steady_clock::now();
  run.order = orderFarthest(positions, max, 1);
  run.orderSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run;
}

}  // namespace

void addDemoCommand(CLI::App& app) {
  struct Options {
    std::string scene = "default";
    std::uint64_t threshold = 10000;
    std::uint32_t maxSurfels = 10000;
    bool json = false;
    int threads = 0;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand("demo", "Run the main job on the embedded default scene (or SCENE)");
  command->add_option("scene", options->scene, "a .gltf/.glb file, or 'default'")->capture_default_str();
  command->add_option("--threshold", options->threshold, "nodes above this many triangles get surfels")
      ->capture_default_str();
  command->add_option("--max-surfels", options->maxSurfels, "surfels to order for the captured node")
      ->check(CLI::Range(1u, 100'000'000u))
      ->capture_default_str();
  command->add_flag("--json", options->json, "print JSON instead of text");
  addThreadsOption(*command, options->threads);
  command->callback([options] {
    runWithThreads(options->threads, [&] {
      const LoadedScene loaded = loadAndAnalyze(options->scene, LoadOptions{});
      const auto surfelNodes = nodesNeedingSurfels(loaded.hierarchy, options->threshold);
      const SurfelRun run = runSurfelPipeline(loaded, options->maxSurfels);
      if (options->json) {
        nlohmann::json report = summaryJson(loaded);
        report["surfel_nodes"] = surfelNodes.size();
        report["captured_node"] = run.node;
        report["captured_surfels"] = run.capture.surfels.size();
        report["coverage"] = run.capture.coverage;
        report["capture_seconds"] = run.captureSeconds;
        report["ordered_surfels"] = run.order.size();
        report["order_seconds"] = run.orderSeconds;
        std::cout << report.dump(2) << "\n";
        return;
      }
      printSummary(loaded);
      std::printf("surfels    %s nodes hold more than %s triangles and would get surfel arrays\n",
                  withThousands(surfelNodes.size()).c_str(), withThousands(options->threshold).c_str());
      std::printf("capture    node %u: %s candidate surfels from %u views at 512 px, coverage %.3f, %.3f s\n",
                  run.node, withThousands(run.capture.surfels.size()).c_str(), run.capture.views,
                  run.capture.coverage, run.captureSeconds);
      std::printf("order      first %s by farthest point, %.3f s\n", withThousands(run.order.size()).c_str(),
                  run.orderSeconds);
    });
  });
}

}  // namespace pbs::cli
