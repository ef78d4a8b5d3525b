// Subtree surface areas: mesh areas computed once per mesh and scaled for similarity transforms; only
// instances under other transforms (non-uniform scales, shears) are summed triangle by triangle.
#include "pbs/scene/surface_area.hpp"

#include <tbb/parallel_for.h>

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

// Every mesh's own area (identity transform), computed in parallel, once.
std::vector<double> meshAreas(const Scene& scene) {
  std::vector<double> areas(scene.meshes.size());
  tbb::parallel_for(std::size_t(0), scene.meshes.size(),
                    [&](std::size_t m) { areas[m] = meshArea(scene.meshes[m], glm::dmat3(1.0)); });
  return areas;
}

// The area of `node`'s subtree with `linear` applied to the node's own frame, instance by instance.
double areaUnder(const Scene& scene, const std::vector<double>& unitAreas, std::uint32_t node,
                 const glm::dmat3& linear) {
  if (const std::optional<double> s2 = similarityScaleSquared(linear)) {
    // Below a similarity every instance scales alike: reduce to the identity, which reuses mesh areas.
    if (*s2 != 1.0 || linear != glm::dmat3(1.0)) return *s2 * areaUnder(scene, unitAreas, node, glm::dmat3(1.0));
  }
  const Node& n = scene.nodes[node];
  const bool identity = linear == glm::dmat3(1.0);
  double area = n.mesh < 0              ? 0.0
                : identity              ? unitAreas[std::size_t(n.mesh)]
                                        : meshArea(scene.meshes[std::size_t(n.mesh)], linear);
  for (std::uint32_t child : n.children)
    area += areaUnder(scene, unitAreas, child, linear * glm::dmat3(scene.nodes[child].local));
  return area;
}

}  // namespace

double subtreeSurfaceArea(const Scene& scene, const Hierarchy& hierarchy, std::uint32_t node) {
  return areaUnder(scene, meshAreas(scene), node, glm::dmat3(hierarchy.world[node]));
}

std::vector<double> ownFrameSurfaceAreas(const Scene& scene, const Hierarchy& hierarchy) {
  const std::vector<double> unitAreas = meshAreas(scene);
  std::vector<double> own(scene.nodes.size(), 0.0);
  // A child placed by a similarity adds s² times its own area; the others (a non-uniform instance
  // placement, say) are summed through their transform — those are the costly ones, done in parallel.
  std::vector<double> underLocal(scene.nodes.size(), -1.0);
  std::vector<std::uint32_t> irregular;
  for (std::uint32_t n : hierarchy.preorder)
    if (!similarityScaleSquared(glm::dmat3(scene.nodes[n].local))) irregular.push_back(n);
  tbb::parallel_for(std::size_t(0), irregular.size(), [&](std::size_t i) {
    const std::uint32_t n = irregular[i];
    underLocal[n] = areaUnder(scene, unitAreas, n, glm::dmat3(scene.nodes[n].local));
  });
  for (auto it = hierarchy.preorder.rbegin(); it != hierarchy.preorder.rend(); ++it) {
    const Node& n = scene.nodes[*it];
    double area = n.mesh < 0 ? 0.0 : unitAreas[std::size_t(n.mesh)];
    for (std::uint32_t child : n.children) {
      const std::optional<double> s2 = similarityScaleSquared(glm::dmat3(scene.nodes[child].local));
      area += s2 ? *s2 * own[child] : underLocal[child];
    }
    own[*it] = area;
  }
  return own;
}

}  // namespace pbs
