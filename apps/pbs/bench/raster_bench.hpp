// `pbs bench raster`: the rasterizer timed against its peers (llvmpipe, Embree) in one run.
#pragma once

#include <pbs/scene/hierarchy.hpp>

#include <nlohmann/json.hpp>

namespace pbs::bench {

struct RasterBenchOptions {
  std::uint32_t resolution = 1024;
  std::uint64_t points = 10'000'000;
  int repeats = 5;
  int threads = 0;  // "all threads" for the multi-threaded runs
};

// Times (a) the eight orthographic capture views of the scene's root box into depth + colour +
// position + normal and (b) `points` random points of 1 px and 4 px, each with pbs on 1 thread and
// on all threads, with llvmpipe and (for the views) with Embree packets; returns the JSON report.
nlohmann::json benchRaster(const Scene& scene, const Hierarchy& hierarchy, const RasterBenchOptions& options);

}  // namespace pbs::bench
