// Subtree surface areas: mesh areas computed once per mesh and scaled for similarity transforms; only
// instances under other transforms (non-uniform scales, shears) are summed triangle by triangle.
#include "pbs/scene/surface_area.hpp"

#include <tbb/parallel_for.h>

#include <cmath>
#include <optional>
#include <vector>

namespace pbs {
namespace {

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

// Every mesh's area vectors, and from them its own area (identity transform), computed in parallel, once.
struct MeshAreas {
  std::vector<TriangleAreaVectors> vectors;
  std::vector<double> unit;
};
MeshAreas meshAreas(const Scene& scene) {
  MeshAreas areas;
  areas.vectors.resize(scene.meshes.size());
  areas.unit.resize(scene.meshes.size());
  tbb::parallel_for(std::size_t(0), scene.meshes.size(), [&](std::size_t m) {
    areas.vectors[m] = TriangleAreaVectors(scene.meshes[m]);
    areas.unit[m] = areas.vectors[m].areaUnder(glm::dmat3(1.0));
  });
  return areas;
}

// The area of `node`'s subtree with `linear` applied to the node's own frame, instance by instance; the
// area of a mesh under a linear map other than the identity is `areaOf(mesh, linear)`, asked for in an
// order that depends on the transforms alone (so a first walk can list the questions and a second
// answer them from a table).
template <class AreaOf>
double areaUnder(const Scene& scene, const std::vector<double>& unitAreas, std::uint32_t node, const glm::dmat3& linear,
                 AreaOf& areaOf) {
  if (const std::optional<double> s2 = similarityScaleSquared(linear)) {
    // Below a similarity every instance scales alike: reduce to the identity, which reuses mesh areas.
    if (*s2 != 1.0 || linear != glm::dmat3(1.0))
      return *s2 * areaUnder(scene, unitAreas, node, glm::dmat3(1.0), areaOf);
  }
  const Node& n = scene.nodes[node];
  const bool identity = linear == glm::dmat3(1.0);
  double area = n.mesh < 0 ? 0.0 : identity ? unitAreas[std::size_t(n.mesh)] : areaOf(std::uint32_t(n.mesh), linear);
  for (std::uint32_t child : n.children)
    area += areaUnder(scene, unitAreas, child, linear * glm::dmat3(scene.nodes[child].local), areaOf);
  return area;
}

// The nodes placed by a transform other than a similarity, in preorder: their subtrees are summed
// through it (the costly part); every other child adds s² times its own area.
std::vector<std::uint32_t> irregularNodes(const Scene& scene, const Hierarchy& hierarchy) {
  std::vector<std::uint32_t> irregular;
  for (std::uint32_t n : hierarchy.preorder)
    if (!similarityScaleSquared(glm::dmat3(scene.nodes[n].local))) irregular.push_back(n);
  return irregular;
}

// ownFrameSurfaceAreas from the mesh areas and each irregular node's subtree area under its local transform.
std::vector<double> sumOwnFrameAreas(const Scene& scene, const Hierarchy& hierarchy,
                                     const std::vector<double>& unitAreas, const std::vector<double>& underLocal) {
  std::vector<double> own(scene.nodes.size(), 0.0);
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

}  // namespace

TriangleAreaVectors::TriangleAreaVectors(const Mesh& mesh) {
  const std::size_t triangles = mesh.indices.size() / 3;
  x_.resize(triangles);
  y_.resize(triangles);
  z_.resize(triangles);
  for (std::size_t t = 0; t < triangles; ++t) {
    const glm::dvec3 a(mesh.positions[mesh.indices[3 * t]]);
    const glm::dvec3 b(mesh.positions[mesh.indices[3 * t + 1]]);
    const glm::dvec3 c(mesh.positions[mesh.indices[3 * t + 2]]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    x_[t] = n.x;
    y_[t] = n.y;
    z_[t] = n.z;
  }
}

double TriangleAreaVectors::areaUnder(const glm::dmat3& linear) const {
  // (L u) × (L v) = cof(L) (u × v), whose columns are the crossed pairs of L's columns.
  const glm::dmat3 cofactor(glm::cross(linear[1], linear[2]), glm::cross(linear[2], linear[0]),
                            glm::cross(linear[0], linear[1]));
  double area = 0.0;
  for (std::size_t t = 0; t < x_.size(); ++t) area += 0.5 * glm::length(cofactor * glm::dvec3(x_[t], y_[t], z_[t]));
  return area;
}

double subtreeSurfaceArea(const Scene& scene, const Hierarchy& hierarchy, std::uint32_t node) {
  const MeshAreas areas = meshAreas(scene);
  const auto areaOf = [&](std::uint32_t mesh, const glm::dmat3& linear) {
    return areas.vectors[mesh].areaUnder(linear);
  };
  return areaUnder(scene, areas.unit, node, glm::dmat3(hierarchy.world[node]), areaOf);
}

std::vector<double> ownFrameSurfaceAreas(const Scene& scene, const Hierarchy& hierarchy) {
  const MeshAreas areas = meshAreas(scene);
  std::vector<double> underLocal(scene.nodes.size(), -1.0);
  const std::vector<std::uint32_t> irregular = irregularNodes(scene, hierarchy);
  tbb::parallel_for(std::size_t(0), irregular.size(), [&](std::size_t i) {
    const std::uint32_t n = irregular[i];
    const auto areaOf = [&](std::uint32_t mesh, const glm::dmat3& linear) {
      return areas.vectors[mesh].areaUnder(linear);
    };
    underLocal[n] = areaUnder(scene, areas.unit, n, glm::dmat3(scene.nodes[n].local), areaOf);
  });
  return sumOwnFrameAreas(scene, hierarchy, areas.unit, underLocal);
}

std::vector<MeshAreaQuery> ownFrameAreaQueries(const Scene& scene, const Hierarchy& hierarchy) {
  std::vector<MeshAreaQuery> queries;
  for (std::uint32_t m = 0; m < scene.meshes.size(); ++m) queries.push_back({m, glm::dmat3(1.0)});
  const std::vector<double> unknown(scene.meshes.size(), 0.0);
  const auto ask = [&](std::uint32_t mesh, const glm::dmat3& linear) {
    queries.push_back({mesh, linear});
    return 0.0;
  };
  for (std::uint32_t n : irregularNodes(scene, hierarchy))
    areaUnder(scene, unknown, n, glm::dmat3(scene.nodes[n].local), ask);
  return queries;
}

std::vector<double> ownFrameSurfaceAreas(const Scene& scene, const Hierarchy& hierarchy,
                                         std::span<const double> answers) {
  const std::vector<double> unitAreas(answers.begin(), answers.begin() + std::ptrdiff_t(scene.meshes.size()));
  std::size_t next = scene.meshes.size();
  const auto answer = [&](std::uint32_t, const glm::dmat3&) { return answers[next++]; };
  std::vector<double> underLocal(scene.nodes.size(), -1.0);
  for (std::uint32_t n : irregularNodes(scene, hierarchy))
    underLocal[n] = areaUnder(scene, unitAreas, n, glm::dmat3(scene.nodes[n].local), answer);
  return sumOwnFrameAreas(scene, hierarchy, unitAreas, underLocal);
}

}  // namespace pbs
