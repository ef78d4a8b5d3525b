// sizedTerrain: a terrain's triangle count chosen from its projected area in the capture views.
#include "sized_terrain.hpp"

#include "raster_bench.hpp"

#include <pbs/scene/generate.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

namespace pbs::bench {
namespace {

// Big enough to resolve the terrain's finest waves (a fortieth of its side) with a few cells each.
constexpr std::uint64_t kProbeTriangles = 2 * 256 * 256;

struct AnalyzedTerrain {
  Scene scene;
  Hierarchy hierarchy;
};

AnalyzedTerrain terrain(std::uint64_t triangles) {
  TerrainOptions options;
  options.triangles = triangles;
  AnalyzedTerrain out{generateTerrain(options), {}};
  out.hierarchy = analyzeHierarchy(out.scene);
  return out;
}

double capturePixelsPerTriangle(const AnalyzedTerrain& terrain, std::uint32_t resolution) {
  return meanProjectedPixels(terrain.scene, terrain.hierarchy,
                             captureCameras(sceneBounds(terrain.scene, terrain.hierarchy), resolution));
}

}  // namespace

double meanProjectedPixels(const Scene& scene, const Hierarchy& hierarchy, std::span<const Camera> cameras) {
  double pixels = 0.0;
  std::uint64_t triangles = 0;
  for (const Camera& camera : cameras) {
    const glm::dmat4 windowFromWorld = windowFromClipMatrix(camera) * camera.clipFromWorld();
    for (std::uint32_t n : hierarchy.preorder) {
      const Node& node = scene.nodes[n];
      if (node.mesh < 0) continue;
      const Mesh& mesh = scene.meshes[std::size_t(node.mesh)];
      const glm::dmat4 windowFromObject = windowFromWorld * hierarchy.world[n];
      const auto window = [&](std::uint32_t index) {
        const glm::dvec4 p = windowFromObject * glm::dvec4(glm::dvec3(mesh.positions[index]), 1.0);
        return glm::dvec2(p) / p.w;
      };
      for (const MeshPart& part : mesh.parts)
        for (std::uint32_t i = part.firstIndex; i < part.firstIndex + part.indexCount; i += 3) {
          const glm::dvec2 a = window(mesh.indices[i]), b = window(mesh.indices[i + 1]),
                           c = window(mesh.indices[i + 2]);
          const glm::dvec2 ab = b - a, ac = c - a;
          pixels += 0.5 * std::abs(ab.x * ac.y - ab.y * ac.x);
          ++triangles;
        }
    }
  }
  return triangles > 0 ? pixels / double(triangles) : 0.0;
}

SizedTerrain sizedTerrain(double pixelsPerTriangle, std::uint32_t resolution) {
  const double projectedPixels =
      capturePixelsPerTriangle(terrain(kProbeTriangles), resolution) * double(kProbeTriangles);
  // The square grid (2·cells² triangles) nearest the asked size.
  const auto cells = std::uint64_t(std::max(1.0, std::round(std::sqrt(projectedPixels / pixelsPerTriangle / 2.0))));
  AnalyzedTerrain sized = terrain(2 * cells * cells);
  const double measured = capturePixelsPerTriangle(sized, resolution);
  return {std::move(sized.scene), std::move(sized.hierarchy), measured};
}

}  // namespace pbs::bench
