// `pbs bench raster --sweep`: the capture measurement (benchCapture) on terrains of falling
// triangle size, so that one run shows whether each contender holds its speed from large
// triangles to sub-pixel ones.
#pragma once

#include "raster_bench.hpp"

#include <pbs/evaluation/svg_plot.hpp>

#include <nlohmann/json.hpp>

#include <vector>

namespace pbs::bench {

struct RasterSweepOptions {
  RasterBenchOptions raster;                                                          // its points are not read
  std::vector<double> pixelsPerTriangle = {1.0 / 16, 1.0 / 4, 1.0, 4.0, 16.0, 64.0};  // each > 0
};

// One sized terrain (sizedTerrain) per entry of options.pixelsPerTriangle, in the order given, each
// measured by benchCapture; the report lists them under "sizes" with their triangle counts and
// throughputs.
nlohmann::json benchRasterSweep(const RasterSweepOptions& options);

// Throughput (million triangles drawn per second, each triangle once per view) against triangle
// size, one series per contender, both axes logarithmic.
Plot rasterSweepPlot(const nlohmann::json& report);

}  // namespace pbs::bench
