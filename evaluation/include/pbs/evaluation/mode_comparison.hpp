// What the figures and the evaluation's other orderings measure: surfels made in memory (with progress
// reported as a step), and views drawn exactly and with surfels, timed and compared.
#pragma once

#include "pbs/evaluation/progress_events.hpp"

#include <pbs/raster/camera.hpp>
#include <pbs/raster/image_metrics.hpp>
#include <pbs/scene/hierarchy.hpp>
#include <pbs/scene/scene.hpp>
#include <pbs/surfels/frame_renderer.hpp>
#include <pbs/surfels/scene_surfels.hpp>
#include <pbs/surfels/surfelize.hpp>

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace pbs {

struct MadeSurfels {
  SceneSurfels surfels;
  SurfelizeStats stats;
  double seconds = 0.0;  // surfelize alone, matching to the scene left out
};

// surfelize(), reported to `progress` as step `label` (arrays done of all), its arrays matched to the scene
// (named `label` in their errors).
MadeSurfels surfelizeInMemory(const Scene& scene, const Hierarchy& hierarchy, const SurfelizeOptions& options,
                              const std::string& label, const ProgressEvents& progress = {});

struct ModeFrames {
  FrameResult exact;
  FrameResult surfels;
  ImageDifference error;  // surfels (A) against exact (B)
};

// One FrameRenderer per mode, each reused over the views so timings match `pbs render`'s.
class ModeComparison {
 public:
  // scene, hierarchy and surfels must outlive the comparison.
  ModeComparison(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels, const LodOptions& lod,
                 std::uint32_t width, std::uint32_t height);

  // Every view exactly, then every view with surfels: each mode runs warm, as in `pbs render --frames`,
  // and no surfel frame pays for the memory an exact frame of a billion triangles just went through.
  // `onFrame(done, total)` after each of the 2 × views frames.
  std::vector<ModeFrames> render(std::span<const Camera> cameras,
                                 const std::function<void(std::size_t, std::size_t)>& onFrame);

 private:
  std::uint32_t width_, height_;
  FrameRenderer exact_;
  FrameRenderer surfels_;
};

}  // namespace pbs
