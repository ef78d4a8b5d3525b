// `pbs figure stream`: a view while its surfels stream in (the paper's conclusion: "the already received
// prefix can be used as an approximation … further transmissions then refine the approximation
// progressively"). Image error against the converged reference over time, at two bandwidths, for
// prefixes streamed chunk by chunk (surfel_stream.hpp) beside whole arrays loaded one by one.
#pragma once

#include <pbs/raster/orbit_camera.hpp>
#include <pbs/surfels/lod_render.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace pbs::cli {

struct StreamFigureOptions {
  std::string scene;    // a .gltf/.glb file, or "default"
  std::string surfels;  // its .surfels file
  Orbit orbit{30.0, 20.0, 2.5};
  std::uint32_t width = 1920, height = 1080;
  LodOptions lod;
  std::vector<double> bandwidths = {1.0, 10.0};  // MB/s (10⁶ bytes a second)
  double seconds = 8.0;                          // simulated time the plot spans
  std::uint32_t steps = 32;                      // frames per series, evenly spread over `seconds`
  std::uint32_t referenceSamples = 64;           // Embree's samples per pixel for the reference
  bool quiet = false;                            // no progress on stderr
};

// Writes `folder`/stream.svg (FLIP over the covered pixels against simulated seconds, one curve per
// bandwidth and order, the frame with every prefix loaded as a level line), stream.csv, stream.json and
// stream.png (rows: a quarter, half and all of the time at the lowest bandwidth; columns: prefixes |
// whole arrays | reference), and prints a row per series.
void writeStreamFigure(const StreamFigureOptions& options, const std::filesystem::path& folder);

}  // namespace pbs::cli
