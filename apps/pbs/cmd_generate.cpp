// `pbs generate default|city|terrain -o F.glb|F.gltf`: writes the procedural scenes as glTF, a binary .glb
// or a .gltf with .bin files.
#include "commands.hpp"
#include "memory_limit.hpp"
#include "scene_report.hpp"

#include <pbs/evaluation/report_numbers.hpp>
#include <pbs/raster/thread_arena.hpp>
#include <pbs/scene/generate.hpp>
#include <pbs/scene/gltf_export.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <stdexcept>

namespace pbs::cli {
namespace {

// Whether `output` names a .gltf (data in .bin files beside it, written mesh by mesh) rather than a .glb.
bool writesGltf(const std::string& output) { return std::filesystem::path(output).extension() == ".gltf"; }

// Writes `scene`, whose meshes `meshAt` reads (the scene's own, or made one at a time), and says what.
void writeAndReport(const Scene& scene, const MeshReader& meshAt, const std::string& output) {
  std::uint64_t bytes = 0;
  if (writesGltf(output)) {
    for (const std::filesystem::path& file : writeGltf(scene, meshAt, output))
      bytes += std::filesystem::file_size(file);
  } else {
    writeGlb(scene, output);
    bytes = std::filesystem::file_size(output);
  }
  const SceneSummary summary = summarizeScene(scene, analyzeStructure(scene));
  std::printf("wrote %s: %s nodes, %s instanced triangles (%s unique), %.1f MB\n", output.c_str(),
              withThousands(summary.nodes).c_str(), withThousands(summary.triangles).c_str(),
              withThousands(summary.uniqueTriangles).c_str(), double(bytes) / 1e6);
}

void writeAndReport(const Scene& scene, const std::string& output) {
  writeAndReport(scene, loadedMeshes(scene), output);
}

// Before a city with --unique is baked into a .glb: its size is known exactly from the instanced city
// (the same draws), so refuse what a .glb cannot hold (one 32-bit chunk) or memory cannot, instead of
// failing or being killed after minutes of work. Memory: the scene, then while writing the glTF binary
// twice (the exporter's buffer, growing, and tinygltf's copy of it). A .gltf is written mesh by mesh.
void requireUniqueCityFits(const std::vector<Scene>& prototypes, const CityOptions& options) {
  CityOptions instanced = options;
  instanced.unique = false;
  const Scene city = generateCity(prototypes, instanced);
  std::uint64_t triangles = 0, sceneBytes = 0, glbBytes = 0;
  for (const Node& node : city.nodes) {
    if (node.mesh < 0) continue;
    const Mesh& mesh = city.meshes[std::size_t(node.mesh)];
    const std::uint64_t vertices = mesh.positions.size(), perVertex = mesh.uvs.empty() ? 24 : 32;
    triangles += mesh.triangleCount();
    sceneBytes += meshBytes(mesh);
    glbBytes += vertices * perVertex + mesh.indices.size() * (vertices < 65535 ? 2 : 4);
  }
  const std::string what = "a city of " + withThousands(triangles) + " unique triangles";
  if (glbBytes > std::numeric_limits<std::uint32_t>::max() - (std::uint64_t(1) << 20))
    throw std::runtime_error(what + " needs " + withThousands(glbBytes >> 20) +
                             " MiB of binary glTF data, more than the 4 GiB a .glb holds: write a .gltf (its data "
                             "in .bin files, written mesh by mesh), or lower --levels or --fanout");
  requireMemory(sceneBytes + 3 * glbBytes, what, 0);
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
  CLI::App* generate = app.add_subcommand("generate", "Write a procedural scene as .glb or .gltf");
  generate->require_subcommand(1);

  CLI::App* plant = generate->add_subcommand("default", "the embedded default scene (an industrial plant)");
  plant->add_option("-o,--output", options->output, "output .glb, or .gltf with its data in .bin files")->required();
  addThreadsOption(*plant, options->threads);
  plant->callback([options] {
    runWithThreads(options->threads, [&] { writeAndReport(generateDefaultScene(), options->output); });
  });

  CLI::App* terrain =
      generate->add_subcommand("terrain", "one flat mesh under one node: a displaced grid, no hierarchy of its own");
  auto terrainOptions = std::make_shared<TerrainOptions>();
  terrain->add_option("--triangles", terrainOptions->triangles, "triangles at least (a square grid)")
      ->check(CLI::Range(std::uint64_t(2), std::uint64_t(2'000'000'000)))
      ->capture_default_str();
  terrain->add_option("--size", terrainOptions->size, "the grid's side in scene units")
      ->check(positiveNumber())
      ->capture_default_str();
  terrain->add_option("--seed", terrainOptions->seed, "seed of the height field")->capture_default_str();
  auto terrainOutput = std::make_shared<std::string>();
  terrain->add_option("-o,--output", *terrainOutput, "output .glb, or .gltf with its data in a .bin file")->required();
  terrain->callback([terrainOptions, terrainOutput] {
    // Vertices and indices in memory, then the exporter's buffer and tinygltf's copy of it.
    const double cells = std::ceil(std::sqrt(double(terrainOptions->triangles) / 2.0));
    const auto sceneBytes = std::uint64_t((cells + 1) * (cells + 1) * 24.0 + cells * cells * 24.0);
    requireMemory(3 * sceneBytes, "a terrain of " + withThousands(terrainOptions->triangles) + " triangles", 0);
    writeAndReport(generateTerrain(*terrainOptions), *terrainOutput);
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
  city->add_flag("--unique", options->city.unique,
                 "share nothing: every instance gets its own copy of its mesh, its placement baked into the "
                 "vertices (the same picture, as many meshes as instances)");
  city->add_option("-o,--output", options->output,
                   "output .glb, or .gltf with its data in .bin files beside it (no 4 GiB limit; with --unique "
                   "written one mesh at a time, so the city need not fit in memory)")
      ->required();
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
      if (options->city.unique && writesGltf(options->output)) {
        const UnbakedCity city = generateUniqueCity(prototypes, options->city);
        writeAndReport(city.scene, city.bake, options->output);
        return;
      }
      if (options->city.unique) requireUniqueCityFits(prototypes, options->city);
      writeAndReport(generateCity(prototypes, options->city), options->output);
    });
  });
}

}  // namespace pbs::cli
