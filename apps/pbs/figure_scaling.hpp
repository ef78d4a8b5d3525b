// `pbs figure scaling`: frame time against scene complexity (the paper's second evaluation). A series
// of generated cities, each surfelized in memory and drawn over an orbit exactly and with surfels.
#pragma once

#include <pbs/surfels/lod_render.hpp>

#include <cstdint>
#include <filesystem>
#include <limits>
#include <pbs/surfels/camera_paths.hpp>

#include <string>
#include <vector>

namespace pbs::cli {

struct ScalingOptions {
  std::vector<std::string> meshes;  // the prototypes every city instances
  std::uint32_t frames = 3;         // views per city along the path
  CameraPath path = CameraPath::Orbit;
  std::uint32_t width = 1920, height = 1080;
  LodOptions lod;                                                          // of the surfels mode
  std::uint64_t maxTriangles = std::numeric_limits<std::uint64_t>::max();  // cities above are left out
  bool quiet = false;                                                      // no progress on stderr
};

// The series: fanout 12 at 1 to 4 levels, 12 to 20,736 instances (bunny: 0.83 M to 1.44 G triangles).
// One fanout keeps the cities alike in shape, so only their size changes along the plot.
inline constexpr std::uint32_t kScalingFanout = 12;
inline constexpr std::uint32_t kScalingMaxLevels = 4;

// Writes `folder`/scaling.csv, scaling.json and scaling.svg (created if missing) and prints a row per
// city. Each city is freed before the next is made. Throws std::runtime_error when even the smallest
// city has more than options.maxTriangles triangles.
void writeScalingFigure(const ScalingOptions& options, const std::filesystem::path& folder);

}  // namespace pbs::cli
