// `pbs prefixes SCENE -o F.png`: prefixes of 100, 200, 400 … surfels of one node drawn side by side, point
// sizes shrinking as the count grows so every prefix covers the surface about equally (the paper's Figure 2).
#include "commands.hpp"
#include "image_files.hpp"
#include "scene_report.hpp"

#include <pbs/evaluation/report_numbers.hpp>
#include <pbs/scene/find_node.hpp>
#include <pbs/scene/mesh_closure.hpp>
#include <pbs/raster/camera.hpp>
#include <pbs/raster/framebuffer.hpp>
#include <pbs/raster/headlight_shading.hpp>
#include <pbs/raster/points.hpp>
#include <pbs/raster/projected_box.hpp>
#include <pbs/raster/thread_arena.hpp>
#include <pbs/surfels/capture.hpp>
#include <pbs/surfels/ordering.hpp>
#include <pbs/surfels/scene_surfels.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

namespace pbs::cli {
namespace {

// The fixed 3/4 view every panel shares: from above, front and right, so three faces of a box show.
const glm::dvec3 kViewDirection = glm::normalize(glm::dvec3(-0.55, -0.45, -0.7));

// An orthographic camera looking along kViewDirection at the box, its square view fitted to the box's
// projected corners with a small margin. A point-like or empty box gets a unit box so the camera stays
// defined.
Camera panelCamera(const Bounds& box, std::uint32_t size) {
  const glm::dvec3 center = box.empty() ? glm::dvec3(0.0) : box.center();
  double radius = 0.5 * glm::length(box.size());
  if (!(radius > 0.0) || !std::isfinite(radius)) radius = 1.0;
  const glm::dvec3 eye = center - kViewDirection * (2.0 * radius);
  const glm::dmat4 view = glm::lookAt(eye, center, glm::dvec3(0.0, 1.0, 0.0));
  double half = 0.0;
  for (int c = 0; c < 8 && !box.empty(); ++c) {
    const glm::dvec3 p{(c & 1) ? box.max.x : box.min.x, (c & 2) ? box.max.y : box.min.y,
                       (c & 4) ? box.max.z : box.min.z};
    const glm::dvec3 eyeSpace(view * glm::dvec4(p, 1.0));
    half = std::max({half, std::abs(eyeSpace.x), std::abs(eyeSpace.y)});
  }
  half = 1.04 * (half > 0.0 ? half : radius);
  return orthographicCamera(view, -half, half, -half, half, 0.5 * radius, 3.5 * radius, size, size);
}

// Point size for k splats covering `surfacePixels` (the surface's silhouette) about once: a closed
// surface faces the camera with about half its surfels, so each visible one stands for 2 ×
// surfacePixels / k pixels, a square of that area. Shrinks as 1/sqrt(k); clamped to [1, 16] pixels.
float pointSizeFor(double surfacePixels, std::size_t k) {
  const double side = k > 0 ? std::sqrt(2.0 * std::max(surfacePixels, 0.0) / static_cast<double>(k)) : 1.0;
  return static_cast<float>(std::clamp(side, 1.0, 16.0));
}

}  // namespace

void addPrefixesCommand(CLI::App& app) {
  struct Options {
    std::string scene;
    std::string node;
    std::string output;
    std::uint32_t resolution = 256;
    std::uint32_t directions = 8;
    SurfelOrdering ordering = SurfelOrdering::Farthest;
    std::uint64_t seed = 1;
    std::uint32_t panels = 8;
    std::uint32_t panelSize = 320;
    int threads = 0;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command =
      app.add_subcommand("prefixes", "Draw a node's surfel prefixes of 100, 200, 400 … side by side as one PNG");
  command->add_option("scene", options->scene, "a .gltf/.glb file, or 'default'")->required();
  command->add_option("--node", options->node, "node name or index (default: the first root)");
  command->add_option("-o,--output", options->output, "output image (PNG)")->required();
  addCaptureOptions(*command, options->resolution, options->directions);
  addOrderingOption(*command, options->ordering);
  command->add_option("--seed", options->seed, "seed of the ordering")->capture_default_str();
  command->add_option("--panels", options->panels, "panels of 100·2^i surfels, i = 0 … panels−1")
      ->check(CLI::Range(1u, 16u))
      ->capture_default_str();
  command->add_option("--panel-size", options->panelSize, "pixels along each side of a panel")
      ->check(CLI::Range(8u, 4096u))
      ->capture_default_str();
  addThreadsOption(*command, options->threads);
  command->callback([options] {
    runWithThreads(options->threads, [&] {
      const LoadedScene loaded = loadAndAnalyze(options->scene, LoadOptions{});
      const std::uint32_t node = findNode(loaded.scene, loaded.hierarchy, options->node, loaded.name);
      CaptureOptions captureOptions;
      captureOptions.resolution = options->resolution;
      captureOptions.directions = options->directions;
      const std::vector<MeshClosure> closures = meshClosures(loaded.scene);  // as surfelize draws each mesh
      captureOptions.meshClosures = closures;
      const CaptureResult capture = captureNode(loaded.scene, loaded.hierarchy, node, captureOptions);

      std::vector<std::uint32_t> counts;
      for (std::uint32_t i = 0; i < options->panels; ++i) counts.push_back(100u << i);
      std::vector<glm::vec3> positions;
      positions.reserve(capture.surfels.size());
      for (const Surfel& surfel : capture.surfels) positions.push_back(surfel.position);
      const std::uint32_t max = counts.back();
      const std::vector<std::uint32_t> order = orderPoints(options->ordering, positions, max, options->seed);

      // The ordered surfels once, in the form drawPoints reads.
      SurfelArray ordered;
      for (std::uint32_t index : order) ordered.surfels.push_back(capture.surfels[index]);
      const SplatArray splats = splatArrayOf(ordered);

      const Bounds& box = loaded.hierarchy.worldBounds[node];
      const std::uint32_t size = options->panelSize;
      const Camera camera = panelCamera(box, size);
      // The surface's share of the box silhouette, as the capture measured it over its views.
      const double surfacePixels = projectedBoxPixels(camera, box) * capture.coverage;
      const std::uint32_t width = size * options->panels;
      std::vector<std::uint8_t> image(std::size_t(width) * size * 4, 0);  // transparent background
      std::printf("node %u (%s): %s surfels captured, coverage %.3f, %s ordering\n", node,
                  loaded.scene.nodes[node].name.c_str(), withThousands(capture.surfels.size()).c_str(),
                  capture.coverage, std::string(orderingName(options->ordering)).c_str());
      for (std::uint32_t panel = 0; panel < options->panels; ++panel) {
        const std::size_t k = std::min<std::size_t>(counts[panel], order.size());
        PointSet set;
        set.positions = std::span(splats.positions).first(k);
        set.normals = std::span(splats.normals).first(k);
        set.colors = std::span(splats.colors).first(k);
        set.worldFromObject = glm::translate(glm::dmat4(1.0), capture.origin);
        set.pointSize = pointSizeFor(surfacePixels, k);
        set.nodeId = node;
        Framebuffer framebuffer = makeFramebuffer(size, size, kChannelColor | kChannelNormal);
        drawPoints(framebuffer, camera, std::span<const PointSet>(&set, 1));
        // The renderer's one shading, so the shape reads without lights; background stays transparent.
        const std::vector<std::uint8_t> rgba = toRgba8(shadeHeadlight(framebuffer, camera));
        for (std::uint32_t y = 0; y < size; ++y)
          std::copy_n(rgba.begin() + std::ptrdiff_t(y) * size * 4, std::size_t(size) * 4,
                      image.begin() + (std::ptrdiff_t(y) * width + std::ptrdiff_t(panel) * size) * 4);
        std::printf("panel %u: %s surfels, point size %.2f px\n", panel, withThousands(k).c_str(),
                    double(set.pointSize));
      }
      writeImage8(options->output, width, size, 4, image);
      std::printf("wrote %s (%u x %u)\n", options->output.c_str(), width, size);
    });
  });
}

}  // namespace pbs::cli
