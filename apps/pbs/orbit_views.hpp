// The cameras of a named path through a loaded scene, and the `--orbit` / `--size` option texts: shared
// by `pbs render --frames` and `pbs eval` so both see the same cameras.
#pragma once

#include <pbs/raster/camera.hpp>
#include <pbs/raster/orbit_camera.hpp>
#include <pbs/surfels/camera_paths.hpp>

#include "scene_report.hpp"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace pbs::cli {

// "AZ,EL,DIST" (degrees, degrees, bounding radii > 0). Throws CLI::ValidationError naming --orbit.
Orbit parseOrbit(const std::string& text);

// "WxH" with 1 ≤ W, H ≤ 16384. Throws CLI::ValidationError naming --size.
std::pair<std::uint32_t, std::uint32_t> parseSize(const std::string& text);

// The cameras of the camera path named `path` (camera_paths.hpp; a name `--path` accepted) over the
// loaded scene; at least one.
std::vector<PathView> pathViews(const LoadedScene& loaded, const std::string& path, const Orbit& orbit,
                                std::uint32_t frames, std::uint32_t width, std::uint32_t height);

}  // namespace pbs::cli
