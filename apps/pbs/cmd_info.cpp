// `pbs info SCENE [--json]`: what a scene holds, and how long it takes to load.
#include "commands.hpp"
#include "scene_report.hpp"

#include <pbs/raster/thread_arena.hpp>

#include <iostream>
#include <memory>

namespace pbs::cli {

void addInfoCommand(CLI::App& app) {
  struct Options {
    std::string scene;
    bool json = false;
    std::uint32_t octree = 0;
    int threads = 0;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand("info", "Summarise a scene: nodes, instances, triangles, bounds, load time");
  command->add_option("scene", options->scene, "a .gltf/.glb file, or 'default' for the embedded scene")->required();
  command->add_flag("--json", options->json, "print JSON instead of text");
  command->add_option("--octree", options->octree, "rebuild as a loose octree with at most N triangles per leaf");
  addThreadsOption(*command, options->threads);
  command->callback([options] {
    runWithThreads(options->threads, [&] {
      const LoadedScene loaded = loadAndAnalyze(options->scene, LoadOptions{options->octree});
      if (options->json)
        std::cout << summaryJson(loaded).dump(2) << "\n";
      else
        printSummary(loaded);
    });
  });
}

}  // namespace pbs::cli
