// `pbs demo`: the main job on the embedded default scene. For now: generate it and summarise it,
// including how many of its nodes are complex enough to get surfels.
#include "commands.hpp"
#include "scene_report.hpp"

#include <pbs/raster/thread_arena.hpp>
#include <pbs/surfels/surfel_nodes.hpp>

#include <cstdio>
#include <iostream>
#include <memory>

namespace pbs::cli {

void addDemoCommand(CLI::App& app) {
  struct Options {
    std::string scene = "default";
    std::uint64_t threshold = 10000;
    bool json = false;
    int threads = 0;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand("demo", "Run the main job on the embedded default scene (or SCENE)");
  command->add_option("scene", options->scene, "a .gltf/.glb file, or 'default'")->capture_default_str();
  command->add_option("--threshold", options->threshold, "nodes above this many triangles get surfels")
      ->capture_default_str();
  command->add_flag("--json", options->json, "print JSON instead of text");
  addThreadsOption(*command, options->threads);
  command->callback([options] {
    runWithThreads(options->threads, [&] {
      const LoadedScene loaded = loadAndAnalyze(options->scene, LoadOptions{});
      const auto surfelNodes = nodesNeedingSurfels(loaded.hierarchy, options->threshold);
      if (options->json) {
        nlohmann::json report = summaryJson(loaded);
        report["surfel_nodes"] = surfelNodes.size();
        std::cout << report.dump(2) << "\n";
        return;
      }
      printSummary(loaded);
      std::printf("surfels    %s nodes hold more than %s triangles and would get surfel arrays\n",
                  withThousands(surfelNodes.size()).c_str(), withThousands(options->threshold).c_str());
    });
  });
}

}  // namespace pbs::cli
