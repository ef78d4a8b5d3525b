// `pbs figure paths`: the named camera paths (camera_paths.hpp) seen from above, drawn over the scene
// rendered exactly, so one can see where each path goes and what it looks at.
#pragma once

#include <pbs/raster/orbit_camera.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>

namespace pbs::cli {

struct PathsFigureOptions {
  std::string scene = "default";              // a .gltf/.glb file, or "default"
  Orbit orbit;                                // the orbit's start, and the approach's direction and start distance
  std::uint32_t frames = 36;                  // per path
  std::uint32_t width = 1024, height = 1024;  // of each of the two panels
};

// Path colours (sRGB), in the order orbit, approach, flythrough; the legend's squares, top left, are
// in the same order.
inline constexpr std::array<std::array<std::uint8_t, 3>, 3> kPathColors = {
    {{31, 119, 180}, {214, 39, 40}, {44, 160, 44}}};

// Writes `folder`/paths.png and paths.json (folder created if missing). paths.png is two panels side by
// side, each a top view (orthographic, looking down −Y; +X to the right, +Z down) of the scene rendered
// exactly: left, every eye of every path (the whole approach and orbit); right, the scene's XZ box
// close up. Each path is a polyline of its eye positions in its colour (closed for the orbit and the
// flythrough), the first eye a larger dot, each eye a small dot with a tick along its view direction;
// the approach's target region is outlined in the approach's colour, the scene's box in grey.
// paths.json holds every eye, forward vector and azimuth, the region and the panels' extents.
void writePathsFigure(const PathsFigureOptions& options, const std::filesystem::path& folder);

}  // namespace pbs::cli
