// Path cameras for a loaded scene and the parsing of the view option texts.
#include "orbit_views.hpp"

#include <CLI/CLI.hpp>
#include <pbs/raster/raster_limits.hpp>

#include <algorithm>
#include <sstream>

namespace pbs::cli {

Orbit parseOrbit(const std::string& text) {
  Orbit orbit;
  char comma1 = 0, comma2 = 0;
  std::istringstream in(text);
  in >> orbit.azimuthDegrees >> comma1 >> orbit.elevationDegrees >> comma2 >> orbit.distance;
  if (!in || comma1 != ',' || comma2 != ',' || !(in >> std::ws).eof() || !(orbit.distance > 0.0))
    throw CLI::ValidationError("--orbit", "expected AZ,EL,DIST in degrees, degrees, bounding radii > 0, got " + text);
  return orbit;
}

std::pair<std::uint32_t, std::uint32_t> parseSize(const std::string& text) {
  unsigned width = 0, height = 0;
  char x = 0;
  std::istringstream in(text);
  in >> width >> x >> height;
  if (!in || (x != 'x' && x != 'X') || !(in >> std::ws).eof() || width < 1 || height < 1 || width > kMaxViewportSize ||
      height > kMaxViewportSize)
    throw CLI::ValidationError("--size",
                               "expected WxH with 1 ≤ W, H ≤ " + std::to_string(kMaxViewportSize) + ", got " + text);
  return {width, height};
}

std::vector<PathView> pathViews(const LoadedScene& loaded, const std::string& path, const Orbit& orbit,
                                std::uint32_t frames, std::uint32_t width, std::uint32_t height) {
  const std::optional<CameraPath> kind = cameraPathFromName(path);
  if (!kind) throw CLI::ValidationError("--path", "expected orbit, approach or flythrough, got " + path);
  return cameraPath(*kind, loaded.hierarchy, loaded.scene.roots, orbit, frames, width, height);
}

}  // namespace pbs::cli
