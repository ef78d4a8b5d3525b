// Whether a mesh is the closed boundary of a solid, and which way it is wound: then a view from outside it
// sees one side of its faces only, and a capture may leave the other out.
#pragma once

#include "pbs/raster/triangles.hpp"
#include "pbs/scene/scene.hpp"

#include <cstdint>
#include <vector>

namespace pbs {

// True when every edge of the mesh's triangles is shared by exactly two of them, run in opposite
// directions (vertices compared by their positions' bits, so split normals or uvs do not open a seam),
// and the enclosed signed volume is positive (front faces outward). Triangles that repeat a position
// have no area and are left out. False for a mesh with no triangles, an index out of range or a
// coordinate that is not finite. A mesh that intersects itself so that some region lies inside it
// inside out (negative winding) is not told apart; no generator or importer check makes one.
bool closedOutward(const Mesh& mesh);

// Which faces of a mesh a view from outside it can see: one byte per mesh, for a capture (drawNodeTriangles).
enum class MeshFacing : std::uint8_t {
  open = 0,           // both sides
  closedOutward = 1,  // closedOutward: the front faces alone
  closedInward = 2,   // closed, but wound inside out (negative signed volume): the back faces alone
};
// closedOutward's test, with its mirror image told apart: a mesh whose triangles, each turned over, would
// be closedOutward is closedInward (horse.glb of the shared scenes is one). Any other is open.
MeshFacing meshFacing(const Mesh& mesh);
// meshFacing of each of the scene's meshes, side by side; a mesh whose arrays are not loaded counts as open.
std::vector<MeshFacing> meshFacings(const Scene& scene);

// The faces a view from outside can see (TriangleDraw::sides).
inline FaceSides visibleSides(MeshFacing facing) {
  return facing == MeshFacing::closedOutward  ? FaceSides::front
         : facing == MeshFacing::closedInward ? FaceSides::back
                                              : FaceSides::both;
}

}  // namespace pbs
