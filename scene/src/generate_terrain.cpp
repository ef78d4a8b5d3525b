// generateTerrain: a height field sampled on a square grid, two triangles per cell.
#include "pbs/raster/seeded_random.hpp"
#include "pbs/scene/generate.hpp"

#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace pbs {
namespace {

// One wave of the height field: amplitude, spatial frequency (radians per unit), direction, phase.
struct Wave {
  double amplitude, frequency, cosine, sine, phase;
};

// Six octaves from the grid's scale down to a fortieth of it, each of half the wavelength and 0.4 times the
// amplitude of the last: the steepest slopes stay below about 55°, rolling hills with small ridges on them.
std::array<Wave, 6> waves(double size, std::uint64_t seed) {
  SeededRandom random(seed);
  std::array<Wave, 6> out{};
  double amplitude = 0.05 * size, wavelength = 0.8 * size;
  for (Wave& w : out) {
    const double angle = random.range(0.0, 2.0 * std::numbers::pi);
    w = {amplitude, 2.0 * std::numbers::pi / wavelength, std::cos(angle), std::sin(angle),
         random.range(0.0, 2.0 * std::numbers::pi)};
    amplitude *= 0.4;
    wavelength *= 0.5;
  }
  return out;
}

}  // namespace

Scene generateTerrain(const TerrainOptions& options) {
  if (options.triangles == 0) throw std::invalid_argument("generateTerrain: no triangles asked for");
  const auto cells = std::uint64_t(std::ceil(std::sqrt(double(options.triangles) / 2.0)));
  if ((cells + 1) * (cells + 1) > std::uint64_t(UINT32_MAX) || 6 * cells * cells > std::uint64_t(UINT32_MAX))
    throw std::invalid_argument("generateTerrain: too many triangles for 32-bit indices");
  const std::uint32_t n = std::uint32_t(cells), side = n + 1;
  const std::array<Wave, 6> field = waves(options.size, options.seed);

  Mesh mesh;
  mesh.name = "terrain";
  mesh.positions.resize(std::size_t(side) * side);
  tbb::parallel_for(std::uint32_t(0), side, [&](std::uint32_t j) {
    for (std::uint32_t i = 0; i < side; ++i) {
      const double x = options.size * (double(i) / n - 0.5), z = options.size * (double(j) / n - 0.5);
      double y = 0.0;
      for (const Wave& w : field) y += w.amplitude * std::sin(w.frequency * (x * w.cosine + z * w.sine) + w.phase);
      mesh.positions[std::size_t(j) * side + i] = glm::vec3(float(x), float(y), float(z));
    }
  });
  mesh.indices.resize(std::size_t(6) * n * n);
  tbb::parallel_for(std::uint32_t(0), n, [&](std::uint32_t j) {
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t a = j * side + i, b = a + 1, c = a + side, d = c + 1;
      std::uint32_t* out = &mesh.indices[(std::size_t(j) * n + i) * 6];
      // Counter-clockwise seen from above (+Y).
      out[0] = a, out[1] = c, out[2] = d, out[3] = a, out[4] = d, out[5] = b;
    }
  });
  mesh.normals = computeVertexNormals(mesh.positions, mesh.indices);
  mesh.parts.push_back(MeshPart{0, std::uint32_t(mesh.indices.size()), 0});
  updateMeshBounds(mesh);

  Scene scene;
  scene.materials.push_back(Material{"ground", glm::vec4(0.45f, 0.55f, 0.32f, 1.0f), -1});
  scene.meshes.push_back(std::move(mesh));
  scene.nodes.push_back(Node{"terrain", glm::dmat4(1.0), {}, 0});
  scene.roots = {0};
  return scene;
}

}  // namespace pbs
