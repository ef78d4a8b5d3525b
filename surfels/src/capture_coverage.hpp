// The projected area of a box in an orthographic view: the denominator of the capture coverage.
#pragma once

#include "pbs/raster/bounds.hpp"
#include "pbs/raster/camera.hpp"

namespace pbs {

// Area in pixels of the convex hull of the box's 8 corners in window space. Requires an orthographic
// camera: the projection is then affine, so corners are projected as offsets from the box centre and
// boxes far from the origin keep their digits. 0 for an empty box.
double projectedBoxPixels(const Camera& orthographic, const Bounds& box);

}  // namespace pbs
