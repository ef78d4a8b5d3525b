// `pbs capture SCENE [--node NAME] -o DIR`: a node's capture views as pictures (the paper's
// Figure 3): per view its base colour, position and normal buffers, and the surfel count.
#include "commands.hpp"
#include "image_files.hpp"
#include "scene_report.hpp"

#include <pbs/evaluation/report_numbers.hpp>
#include <pbs/scene/find_node.hpp>
#include <pbs/scene/mesh_closure.hpp>
#include <pbs/raster/thread_arena.hpp>
#include <pbs/surfels/capture.hpp>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <vector>

namespace pbs::cli {
namespace {

// One buffer as RGBA8: `toColor` maps a covered pixel; uncovered pixels are transparent.
template <typename ToColor>
std::vector<std::uint8_t> picture(const Framebuffer& gbuffer, ToColor toColor) {
  std::vector<std::uint8_t> rgba(gbuffer.pixelCount() * 4, 0);
  for (std::size_t i = 0; i < gbuffer.pixelCount(); ++i) {
    if (!gbuffer.covered(i)) continue;
    const glm::u8vec4 c = toColor(i);
    for (int k = 0; k < 4; ++k) rgba[i * 4 + std::size_t(k)] = c[k];
  }
  return rgba;
}

glm::u8vec4 unitToRgba(const glm::vec3& v) {  // [-1, 1]³ → RGB, opaque
  return glm::u8vec4(glm::clamp(v * 0.5f + 0.5f, 0.0f, 1.0f) * 255.0f + 0.5f, 255);
}

}  // namespace

void addCaptureCommand(CLI::App& app) {
  struct Options {
    std::string scene;
    std::string node;
    std::string output;
    std::string backend = "raster";
    CaptureOptions capture;
    bool json = false;
    int threads = 0;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand("capture", "Write a node's capture views (colour, position, normal) as PNG");
  command->add_option("scene", options->scene, "a .gltf/.glb file, or 'default'")->required();
  command->add_option("--node", options->node, "node name or index (default: the first root)");
  command->add_option("-o,--output", options->output, "output folder (created if missing)")->required();
  addCaptureOptions(*command, options->capture.resolution, options->capture.directions);
  command->add_option("--backend", options->backend, "raster or embree")
      ->check(CLI::IsMember({"raster", "embree"}))
      ->capture_default_str();
  command->add_flag("--json", options->json, "print JSON instead of text");
  addThreadsOption(*command, options->threads);
  command->callback([options] {
    runWithThreads(options->threads, [&] {
      const LoadedScene loaded = loadAndAnalyze(options->scene, LoadOptions{});
      const std::uint32_t node = findNode(loaded.scene, loaded.hierarchy, options->node, loaded.name);
      const std::filesystem::path folder(options->output);
      std::filesystem::create_directories(folder);
      const Bounds& box = loaded.hierarchy.worldBounds[node];
      const glm::vec3 halfSize = glm::max(glm::vec3(box.size()) * 0.5f, glm::vec3(1e-30f));
      CaptureOptions capture = options->capture;
      const std::vector<MeshClosure> closures = meshClosures(loaded.scene);  // as surfelize draws each mesh
      capture.meshClosures = closures;
      capture.backend =
          options->backend == "embree" ? CaptureOptions::Backend::Embree : CaptureOptions::Backend::Raster;
      capture.onView = [&](std::uint32_t view, const Camera& camera, const Framebuffer& g) {
        const std::string prefix = "view" + std::to_string(view) + "_";
        const auto write = [&](const char* name, const std::vector<std::uint8_t>& rgba) {
          writeImage8(folder / (prefix + name + ".png"), camera.width, camera.height, 4, rgba);
        };
        write("color", picture(g, [&](std::size_t i) { return g.color[i]; }));
        // Positions are relative to the box centre: scaled by the half size they span [-1, 1]³.
        write("position", picture(g, [&](std::size_t i) { return unitToRgba(g.position[i] / halfSize); }));
        write("normal", picture(g, [&](std::size_t i) { return unitToRgba(g.normal[i]); }));
      };
      const CaptureResult result = captureNode(loaded.scene, loaded.hierarchy, node, capture);
      if (options->json) {
        // With what the capture used: its G-buffer, of which each view clears depth alone.
        const nlohmann::json report = {{"scene", loaded.name},
                                       {"node", node},
                                       {"views", result.views},
                                       {"surfels", result.surfels.size()},
                                       {"coverage", result.coverage},
                                       {"output", folder.string()},
                                       {"used",
                                        {{"backend", options->backend},
                                         {"gbuffer", channelNames(kCaptureChannels)},
                                         {"cleared_each_view", channelNames(kCaptureClearedChannels)}}}};
        std::cout << report.dump(2) << "\n";
      } else {
        std::printf("node %u (%s): %u views of %s, %s surfels, coverage %.3f; images in %s\n", node,
                    loaded.scene.nodes[node].name.c_str(), result.views, options->scene.c_str(),
                    withThousands(result.surfels.size()).c_str(), result.coverage, folder.string().c_str());
      }
    });
  });
}

}  // namespace pbs::cli
