// `pbs figure views`: image quality from near to far (the paper's third evaluation). One direction of
// view at three distances, each drawn exactly and with surfels, side by side with their difference.
#pragma once

#include <pbs/surfels/lod_render.hpp>
#include <pbs/surfels/surfelize.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>

namespace pbs::cli {

struct ViewsOptions {
  std::string scene;    // a .gltf/.glb file, or "default"
  std::string surfels;  // its .surfels file; empty: made in memory with `surfelize`
  SurfelizeOptions surfelize;
  std::uint32_t width = 1920, height = 1080;
  LodOptions lod;                                  // of the surfels mode
  std::array<double, 2> direction = {30.0, 20.0};  // azimuth and elevation, degrees (orbit_camera.hpp)
  // Near, middle, far, in bounding radii from the centre. On the default scene at 1920×1080 the LOD
  // moves from ~40 nodes drawn as geometry and ~200 as surfels (near: the plant fills the frame), to
  // ~6 and ~50 (middle: the whole plant), to none and a handful (far: all surfels).
  std::array<double, 3> distances = {0.5, 1.5, 6.0};
  bool quiet = false;  // no progress on stderr
};

// Writes `folder`/views.png (rows near, middle, far; columns exact | surfels | |difference| ×
// kDifferenceGain), views.csv and views.json (created if missing), and prints a row per view.
void writeViewsFigure(const ViewsOptions& options, const std::filesystem::path& folder);

}  // namespace pbs::cli
