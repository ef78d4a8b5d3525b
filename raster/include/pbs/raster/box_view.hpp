// Orthographic cameras fitted to a bounding box: the capture views of the paper (Sec. 2.1).
#pragma once

#include "pbs/raster/bounds.hpp"
#include "pbs/raster/camera.hpp"

#include <cstdint>
#include <vector>

namespace pbs {

// The eight directions from the corners of a box toward its centre, (±1, ±1, ±1)/√3.
std::vector<glm::dvec3> boxCornerDirections();

// An orthographic camera looking along `direction` at the box, its view volume fitted to the
// box's projection so that the larger side spans `resolution` pixels (the other side gets as many
// whole pixels as it needs, at least 1). Near and far enclose the box with a small margin.
// Defined for flat and point-like boxes too: a box of zero extent in the view plane gets pixels of
// a size derived from its largest extent (or 1 when the box is a single point).
Camera boxViewCamera(const Bounds& box, const glm::dvec3& direction, std::uint32_t resolution);

}  // namespace pbs
