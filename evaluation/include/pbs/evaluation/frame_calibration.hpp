// `pbs calibrate`: what a frame costs on this machine, fitted from timed frames (FrameCosts), and the
// small file `--calibration` reads it back from.
#pragma once

#include "pbs/evaluation/progress_events.hpp"

#include <pbs/raster/camera.hpp>
#include <pbs/scene/hierarchy.hpp>
#include <pbs/scene/scene.hpp>
#include <pbs/surfels/frame_cost.hpp>
#include <pbs/surfels/frame_renderer.hpp>
#include <pbs/surfels/lod_render.hpp>

#include <nlohmann/json.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pbs {

// One way of cutting the hierarchy, and drawing its geometry, that the calibration times every view with.
struct CalibrationCut {
  std::string name;  // "threshold=32+geometry=raster", "primitives=4000000+geometry=rays"
  LodOptions lod;
};

// Cuts from coarse to fine around `base` (its other options kept): thresholds of 32 and 128 pixels and
// budgets of 0.25 to 16 million primitives, so that the frames span surfel-heavy to geometry-heavy work,
// each with its geometry drawn by the rasterizer and by rays (so both drawers' terms are fitted).
std::vector<CalibrationCut> calibrationCuts(const LodOptions& base);

struct CalibrationFrame {
  std::string cut;
  std::uint32_t view = 0;
  // The repeat of median time (the slower of two), less reading surfels and building BVHs (work a budget does not
  // pay per frame).
  TimedFrame timed;
};

struct FrameCalibration {
  FrameCostFit fit;
  std::vector<CalibrationFrame> frames;
};

// Renders every camera under every cut in surfels mode, `repeats` times each (at least 1), keeps each
// frame's median time and fits FrameCosts to them (fitFrameCosts, at `quantile`); then times a budget's
// traversal per node it weighs (FrameCosts::perNodeWeighed) and the upscale to the cameras' size
// (FrameCosts::upscalePerPixel). `sources` as for FrameRenderer (surfels or a cache).
FrameCalibration calibrateFrameCosts(const Scene& scene, const Hierarchy& hierarchy, const FrameSources& sources,
                                     std::span<const Camera> cameras, std::span<const CalibrationCut> cuts,
                                     std::uint32_t repeats, double quantile, const ProgressEvents& progress = {});

// The calibration file: the costs (seconds per unit), the fit's error, and the frames it was fitted to.
nlohmann::json calibrationJson(const FrameCalibration& calibration);

// The costs of a calibration file's JSON; InputError naming `file` and the missing or bad field.
FrameCosts frameCostsFromJson(const nlohmann::json& json, std::string_view file);

}  // namespace pbs
