// The projected area of a box: the capture coverage's denominator, and the size the LOD renderer
// compares with its threshold (paper, Sec. 2.1 and 3).
#pragma once

#include "pbs/raster/bounds.hpp"
#include "pbs/raster/camera.hpp"

namespace pbs {

// Area in pixels of the convex hull of the box's 8 corners in window space (its silhouette), unclipped:
// parts outside the viewport count. 0 for an empty box. With a perspective camera, +infinity when a
// corner lies on or behind the eye plane (the box surrounds or touches the eye: no finite size). An
// orthographic camera's projection is affine, so its corners are projected as offsets from the box
// centre and boxes far from the origin keep their digits.
double projectedBoxPixels(const Camera& camera, const Bounds& box);

}  // namespace pbs
