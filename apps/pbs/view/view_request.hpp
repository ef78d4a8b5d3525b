// What the browser asks `pbs view` for: one frame's camera, what to show and how, parsed from a query
// string and validated, so that a bad value is an HTTP 400 with a message rather than a crash.
#pragma once

#include <pbs/raster/orbit_camera.hpp>
#include <pbs/surfels/lod_render.hpp>

#include <glm/glm.hpp>

#include <cstdint>
#include <map>
#include <optional>
#include <string>

namespace pbs::cli {

// Surfels, the rasterizer, rays; the surfel frame against a 16-sample ray-cast reference, as the absolute
// difference (×4) or as its FLIP map; the surfel frame tinted by what drew each pixel (geometry, surfels,
// a prefix thinned by a transition band); or one node's first `prefix` surfels alone (the paper's Fig. 2).
enum class ViewShow { Surfels, Exact, Embree, Difference, Flip, Source, Prefix };
const char* viewShowName(ViewShow show);

enum class ViewEncoding { Jpeg, Png };  // JPEG while moving (small, fast), PNG once still (exact pixels)

// The largest frame the viewer renders (a 4K screen); requests are refused above it.
inline constexpr std::uint32_t kMaxViewWidth = 3840;
inline constexpr std::uint32_t kMaxViewHeight = 2160;

struct ViewRequest {
  std::string client = "anonymous";  // one browser tab: its newer frames supersede its older ones
  std::uint64_t sequence = 0;        // increasing per client
  std::uint32_t width = 1280, height = 720;
  // The camera: an orbit (pbs render's --orbit: degrees, degrees, scene radii) around `target`. With the
  // target at the scene's centre it is exactly `pbs render --orbit AZ,EL,DIST`'s camera.
  glm::dvec3 target{0.0};
  Orbit orbit;
  ViewShow show = ViewShow::Surfels;
  std::uint32_t samples = 1;  // 1, 4, 16 or 64 (supersampling.hpp)
  ViewEncoding encoding = ViewEncoding::Png;
  LodOptions lod;  // threshold, overdraw, splat, point size and budget from the request; the rest default
  std::optional<std::uint32_t> node;  // show=prefix's node, and the node /api/node describes
  std::uint32_t prefix = 0;           // show=prefix: surfels drawn (clamped to the array)
  std::uint32_t x = 0, y = 0;         // /api/pick: a pixel of the frame
};

// Parses a query's parameters (each at most once); `defaults` gives the target (the scene's centre) and
// the LOD options the request changes. Throws std::invalid_argument naming the parameter and the value:
// an unknown name, a value that is not a number or out of its range, a name outside its choices.
ViewRequest parseViewRequest(const std::multimap<std::string, std::string>& parameters, const ViewRequest& defaults);

}  // namespace pbs::cli
