// The views of an orbit around a scene, and the `--orbit` / `--size` option texts: shared by
// `pbs render --frames` and `pbs eval` so both see the same cameras.
#pragma once

#include <pbs/raster/bounds.hpp>
#include <pbs/raster/camera.hpp>
#include <pbs/raster/orbit_camera.hpp>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace pbs::cli {

// "AZ,EL,DIST" (degrees, degrees, bounding radii > 0). Throws CLI::ValidationError naming --orbit.
Orbit parseOrbit(const std::string& text);

// "WxH" with 1 ≤ W, H ≤ 16384. Throws CLI::ValidationError naming --size.
std::pair<std::uint32_t, std::uint32_t> parseSize(const std::string& text);

struct OrbitView {
  double azimuthDegrees = 0.0;
  Camera camera;
};

// `frames` cameras (at least one) around the scene's bounding sphere (centre of `bounds`, radius half
// its diagonal): frame f at azimuth orbit.azimuthDegrees + 360·f/frames, the rest of `orbit` as given.
std::vector<OrbitView> orbitViews(const Bounds& bounds, const Orbit& orbit, std::uint32_t frames, std::uint32_t width,
                                  std::uint32_t height);

}  // namespace pbs::cli
