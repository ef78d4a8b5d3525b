// Whether a mesh is the closed, outward-facing boundary of a solid: then a view from outside it sees
// its front faces only, and a capture may leave its back faces out.
#pragma once

#include "pbs/scene/scene.hpp"

namespace pbs {

// True when every edge of the mesh's triangles is shared by exactly two of them, run in opposite
// directions (vertices compared by their positions' bits, so split normals or uvs do not open a seam),
// and the enclosed signed volume is positive (front faces outward). Triangles that repeat a position
// have no area and are left out. False for a mesh with no triangles, an index out of range or a
// coordinate that is not finite. A mesh that intersects itself so that some region lies inside it
// inside out (negative winding) is not told apart; no generator or importer check makes one.
bool closedOutward(const Mesh& mesh);

}  // namespace pbs
