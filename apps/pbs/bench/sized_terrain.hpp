// Terrains whose triangles cover a chosen mean area in the capture views: the mesh family that
// `pbs bench raster --sweep` times the capture on.
#pragma once

#include <pbs/raster/camera.hpp>
#include <pbs/scene/hierarchy.hpp>

#include <cstdint>
#include <span>

namespace pbs::bench {

// The mean area, in pixels, that a triangle of `scene` projects to in `cameras` (orthographic ones,
// as the capture's: nothing is behind an eye): the projected areas of every drawn triangle in every
// camera, hidden or not, summed, over triangles × cameras.
double meanProjectedPixels(const Scene& scene, const Hierarchy& hierarchy, std::span<const Camera> cameras);

struct SizedTerrain {
  Scene scene;
  Hierarchy hierarchy;
  double pixelsPerTriangle = 0.0;  // measured on this mesh (meanProjectedPixels in its capture views)
};

// A terrain (generateTerrain) whose triangles project to `pixelsPerTriangle` pixels on average in
// its eight capture views at `resolution`. The terrain's surface is the same at every tessellation,
// so its projected area is measured once on a probe terrain and shared among the triangles of the
// nearest square grid: whole cells put the measured size within a factor ((n ± ½)/n)² of the asked
// one for n cells a side (coarse only for large triangles at small resolutions).
SizedTerrain sizedTerrain(double pixelsPerTriangle, std::uint32_t resolution);

}  // namespace pbs::bench
