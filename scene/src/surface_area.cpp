// subtreeSurfaceArea: mesh areas computed once per mesh and scaled for similarity transforms.
#include "pbs/scene/surface_area.hpp"

#include "pbs/scene/scene_draws.hpp"

#include <cmath>
#include <optional>
#include <vector>

namespace pbs {
namespace {

double meshArea(const Mesh& mesh, const glm::dmat3& linear) {
  double area = 0.0;
  for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const glm::dvec3 a = linear * glm::dvec3(mesh.positions[mesh.indices[i]]);
    const glm::dvec3 b = linear * glm::dvec3(mesh.positions[mesh.indices[i + 1]]);
    const glm::dvec3 c = linear * glm::dvec3(mesh.positions[mesh.indices[i + 2]]);
    area += 0.5 * glm::length(glm::cross(b - a, c - a));
  }
  return area;
}

// The squared scale s² when `linear` is s × a rotation (or reflection), else nothing.
std::optional<double> similarityScaleSquared(const glm::dmat3& linear) {
  const glm::dmat3 gram = glm::transpose(linear) * linear;
  const double s2 = (gram[0][0] + gram[1][1] + gram[2][2]) / 3.0;
  const double tolerance = 1e-9 * s2;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      if (std::abs(gram[c][r] - (c == r ? s2 : 0.0)) > tolerance) return std::nullopt;
  return s2;
}

}  // namespace

double subtreeSurfaceArea(const Scene& scene, const Hierarchy& hierarchy, std::uint32_t node) {
  std::vector<double> unitArea(scene.meshes.size(), -1.0);
  double area = 0.0;
  for (std::uint32_t n : subtreeNodes(scene, node)) {
    const std::int32_t m = scene.nodes[n].mesh;
    if (m < 0) continue;
    const Mesh& mesh = scene.meshes[std::size_t(m)];
    const glm::dmat3 linear(hierarchy.world[n]);
    if (const std::optional<double> s2 = similarityScaleSquared(linear)) {
      double& own = unitArea[std::size_t(m)];
      if (own < 0.0) own = meshArea(mesh, glm::dmat3(1.0));
      area += *s2 * own;
    } else {
      area += meshArea(mesh, linear);
    }
  }
  return area;
}

}  // namespace pbs
