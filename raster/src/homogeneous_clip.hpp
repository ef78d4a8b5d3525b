// Clipping a triangle in homogeneous clip space against near, far and the guard band.
#pragma once

#include <glm/glm.hpp>

namespace pbs::triangles {

struct ClipVertex {
  glm::dvec4 clip;
  glm::dvec3 barycentric;  // within the source triangle, carried along for its attributes
};

// Room for a triangle cut by all six planes, plus slack for rounding near-degenerate polygons.
inline constexpr int kMaxClipVertices = 16;

// Sutherland–Hodgman against near (z ≥ −w), far (z ≤ w), then the guard band (|x| ≤ guardX·w,
// |y| ≤ guardY·w), in that order. A plane that every vertex is inside changes nothing, so the
// result equals near/far clipping alone whenever the polygon lies within the guard band. Writes
// the convex polygon (fewer than 3 vertices: nothing left) and returns its vertex count.
int clipTriangle(const ClipVertex (&triangle)[3], double guardX, double guardY,
                 ClipVertex (&polygon)[kMaxClipVertices]);

}  // namespace pbs::triangles
