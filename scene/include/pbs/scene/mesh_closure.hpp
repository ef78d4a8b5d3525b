// Whether a mesh is the closed boundary of a solid, and which way it is wound: then a view from outside it
// sees one side of its faces only, and a capture may leave the other out.
#pragma once

#include "pbs/raster/bounds.hpp"
#include "pbs/raster/triangles.hpp"
#include "pbs/scene/scene.hpp"

#include <cstdint>
#include <vector>

namespace pbs {

// Which faces of a mesh a view from outside it can see: a capture draws those alone (drawNodeTriangles).
enum class MeshFacing : std::uint8_t {
  open = 0,           // both sides
  closedOutward = 1,  // the front faces (the back faces only through the holes: MeshClosure)
  closedInward = 2,   // wound inside out (negative signed volume): the back faces (the front ones through the holes)
};

// A mesh that is closed, or would be once each of its holes were capped: every edge run at most once each way,
// the edges run one way only (the boundary) forming loops, each connected part of them a hole. Seen from
// outside the mesh's box, a ray leaving a face of the hidden side runs into the solid and must leave it
// through a face of the visible side, nearer, or through a hole's cap. Capped by a cone from the hole's
// vertices, which lies in their box, so the hidden side can show only where those boxes project. At most
// 64 holes; a mesh with more, or whose boundary is no set of loops, or that encloses no volume, is open.
struct MeshClosure {
  MeshFacing facing = MeshFacing::open;
  std::vector<Bounds> holes;  // in the mesh's frame, a box per hole (none for a mesh closed as it is)
};

// Edges are compared by their vertices' positions' bits, so split normals or uvs do not open a seam, and
// triangles that repeat a position have no area and are left out. A mesh with no triangles, an index out of
// range or a coordinate that is not finite is open. A mesh that intersects itself so that some region lies
// inside it inside out is not told apart; no generator or importer check makes one. horse.glb of the shared
// scenes is closed, wound inward; bunny.glb has five holes, in its base.
MeshClosure meshClosure(const Mesh& mesh);
// meshClosure of each of the scene's meshes, side by side; a mesh whose arrays are not loaded counts as open.
std::vector<MeshClosure> meshClosures(const Scene& scene);

// The faces a view from outside can see, holes aside (TriangleDraw::sides).
inline FaceSides visibleSides(MeshFacing facing) {
  return facing == MeshFacing::closedOutward  ? FaceSides::front
         : facing == MeshFacing::closedInward ? FaceSides::back
                                              : FaceSides::both;
}

}  // namespace pbs
