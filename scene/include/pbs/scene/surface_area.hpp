// Surface area of a node's subtree: the A of the blue-noise measure ρ(k) (NOTES.md).
#pragma once

#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/scene.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace pbs {

// The summed area of every triangle of every mesh instance in `node`'s subtree, each through its
// hierarchy.world transform (so a hierarchy rooted in a node's own frame gives the area in that frame).
// Degenerate triangles add 0. Instances under a similarity transform (rotation × uniform scale) reuse
// the mesh's own area, so a billion instanced triangles cost one pass over each distinct mesh.
double subtreeSurfaceArea(const Scene& scene, const Hierarchy& hierarchy, std::uint32_t node);

// For every node the area of its subtree in the node's own frame (its own transform left out: the frame
// surfel arrays are made in), all at once: bottom-up, each subtree summed once, so a billion instanced
// triangles cost one pass over each distinct mesh plus the instances under non-similarity transforms.
std::vector<double> ownFrameSurfaceAreas(const Scene& scene, const Hierarchy& hierarchy);

// A mesh's areas under linear maps: per triangle the vector (b − a) × (c − a), in double, once. A map L takes
// it to cof(L) times it (cof(L) = det(L) L^−T, defined for singular L too), so each area is one matrix product
// a triangle, not three vertex transforms (a generated city asks for 20,000 of them). areaUnder(linear): the
// summed area of the mesh's triangles under `linear`; under the identity, the vectors' own lengths to the bit
// (cof(I) = I, and I times a finite vector is that vector).
class TriangleAreaVectors {
 public:
  TriangleAreaVectors() = default;  // of a mesh without triangles
  explicit TriangleAreaVectors(const Mesh& mesh);
  double areaUnder(const glm::dmat3& linear) const;

 private:
  std::vector<double> x_, y_, z_;  // per triangle, the components of (b − a) × (c − a)
};

// ownFrameSurfaceAreas for a scene whose vertices are read elsewhere (a scan over its meshes): first the
// mesh areas it needs, each TriangleAreaVectors(scene.meshes[mesh]).areaUnder(linear) — every mesh under the identity,
// in mesh order, then those of instances under non-similarity transforms, in the order the sums use them — then the
// areas from their answers, bit for bit those of ownFrameSurfaceAreas(scene, hierarchy). Neither reads a vertex;
// `hierarchy` needs only its preorder (analyzeStructure's will do).
struct MeshAreaQuery {
  std::uint32_t mesh;
  glm::dmat3 linear;
};
std::vector<MeshAreaQuery> ownFrameAreaQueries(const Scene& scene, const Hierarchy& hierarchy);
std::vector<double> ownFrameSurfaceAreas(const Scene& scene, const Hierarchy& hierarchy,
                                         std::span<const double> answers);

}  // namespace pbs
