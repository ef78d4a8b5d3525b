// `pbs generate default|city -o F.glb`: writes the procedural scenes as glTF binary files.
#include "commands.hpp"
#include "scene_report.hpp"

#include <pbs/raster/thread_arena.hpp>
#include <pbs/scene/generate.hpp>
#include <pbs/scene/gltf_export.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

namespace pbs::cli {
namespace {

void writeAndReport(const Scene& scene, const std::string& output) {
  writeGlb(scene, output);
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  const SceneSummary summary = summarizeScene(scene, hierarchy);
  std::printf("wrote %s: %s nodes, %s instanced triangles (%s unique), %.1f MB\n", output.c_str(),
              withThousands(summary.nodes).c_str(), withThousands(summary.triangles).c_str(),
              withThousands(summary.uniqueTriangles).c_str(), double(std::filesystem::file_size(output)) / 1e6);
}

}  // namespace

void addGenerateCommand(CLI::App& app) {
  struct Options {
    std::string output;
    std::vector<std::string> meshes;
    CityOptions city;
    int threads = 0;
  };
  auto options = std::make_shared<Options>();
  CLI::App* generate = app.add_subcommand("generate", "Write a procedural scene as .glb");
  generate->require_subcommand(1);

  CLI::App* plant = generate->add_subcommand("default", "the embedded default scene (an industrial plant)");
  plant->add_option("-o,--output", options->output, "output .glb")->required();
  addThreadsOption(*plant, options->threads);
  plant->callback([options] {
    runWithThreads(options->threads, [&] { writeAndReport(generateDefaultScene(), options->output); });
  });

  CLI::App* city = generate->add_subcommand("city", "instances of given meshes in a deep hierarchy");
  city->add_option("--mesh", options->meshes, "a .gltf/.glb file to instance (repeat for several)")->required();
  city->add_option("--levels", options->city.levels, "levels of blocks below the root")
      ->check(CLI::Range(1, 12))
      ->capture_default_str();
  city->add_option("--fanout", options->city.fanout, "children per block")
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
  city->add_option("--seed", options->city.seed, "seed for placement, rotation and scale")->capture_default_str();
  city->add_option("-o,--output", options->output, "output .glb")->required();
  addThreadsOption(*city, options->threads);
  city->callback([options] {
    // Leaves = fanout^levels; refuse sizes whose node arrays alone would not fit in memory.
    const double leaves = std::pow(double(options->city.fanout), double(options->city.levels));
    if (leaves > 5e7)
      throw CLI::ValidationError("--fanout/--levels", "fanout^levels = " + std::to_string(leaves) +
                                                          " leaves; at most 50,000,000 are supported");
    runWithThreads(options->threads, [&] {
      std::vector<Scene> prototypes;
      for (const std::string& mesh : options->meshes) prototypes.push_back(loadScene(mesh).scene);
      writeAndReport(generateCity(prototypes, options->city), options->output);
    });
  });
}

}  // namespace pbs::cli
