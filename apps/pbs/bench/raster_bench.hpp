// `pbs bench raster`: the rasterizer timed against its peers (llvmpipe, Embree) in one run.
#pragma once

#include <pbs/raster/camera.hpp>
#include <pbs/scene/hierarchy.hpp>

#include <nlohmann/json.hpp>

#include <cstdint>
#include <vector>

namespace pbs::bench {

struct RasterBenchOptions {
  std::uint32_t resolution = 1024;
  std::uint64_t points = 10'000'000;
  int repeats = 5;
  int threads = 0;  // "all threads" for the multi-threaded runs
};

// The box the capture views are fitted to: the union of the roots' world boxes.
Bounds sceneBounds(const Scene& scene, const Hierarchy& hierarchy);

// The eight orthographic capture views of `box`, its larger projected side `resolution` pixels.
std::vector<Camera> captureCameras(const Bounds& box, std::uint32_t resolution);

// The capture measurement of one scene: the eight capture views into depth + colour + position +
// normal by pbs on one thread and on all, by Embree packets and by llvmpipe, in interleaved rounds;
// each with its median seconds and covered pixels, and the ratios (the llvmpipe entry says why it
// is missing where OSMesa is not there).
nlohmann::json benchCapture(const Scene& scene, const Hierarchy& hierarchy, const RasterBenchOptions& options);

// Times (a) the eight orthographic capture views of the scene's root box into depth + colour +
// position + normal and (b) `points` random points of 1 px and 4 px, each with pbs on 1 thread and
// on all threads, with llvmpipe and (for the views) with Embree packets; returns the JSON report.
nlohmann::json benchRaster(const Scene& scene, const Hierarchy& hierarchy, const RasterBenchOptions& options);

}  // namespace pbs::bench
