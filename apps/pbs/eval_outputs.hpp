// What `pbs eval` writes: eval.csv (one row per setting and frame), summary.json (medians and worst
// cases per setting), error_vs_time.svg (one marker per setting, the Pareto front drawn).
#pragma once

#include "eval_run.hpp"
#include "eval_settings.hpp"
#include "svg_plot.hpp"

#include <pbs/raster/orbit_camera.hpp>

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace pbs::cli {

// The CSV header, in column order.
inline constexpr const char* kEvalCsvHeader =
    "setting,frame,azimuth,seconds,traverse_seconds,raster_seconds,triangles,surfels,rmse,psnr,ssim,hole_fraction";

// Per setting, over its frames.
struct EvalSummary {
  std::string name;
  double medianSeconds = 0.0, medianTraverseSeconds = 0.0, medianRasterSeconds = 0.0;
  double medianTriangles = 0.0, medianSurfels = 0.0;
  double medianRmse = 0.0, worstRmse = 0.0;  // worst: largest
  double medianPsnr = 0.0, worstPsnr = 0.0;  // worst: smallest; +inf when identical
  double medianSsim = 1.0, worstSsim = 1.0;  // worst: smallest
  double medianHoleFraction = 0.0, worstHoleFraction = 0.0;
};


EvalSummary summarize(const std::string& name, const std::vector<EvalFrame>& frames);

// Indices of the points no other point beats in both coordinates (smaller x and smaller y, at least
// one strictly), sorted by x: the settings worth choosing when both time and error count.
std::vector<std::size_t> paretoFront(const std::vector<std::pair<double, double>>& points);

// Rows in setting order, frames in order; psnr is written "inf" for identical images.
std::string evalCsv(const std::vector<EvalSetting>& settings, const EvalResults& results);

struct EvalRunInfo {
  std::string scene;
  std::string surfels;  // the .surfels file
  std::uint32_t width = 0, height = 0, frames = 0;
  Orbit orbit;
  std::optional<std::size_t> baseline;  // index into the settings
};

// summary.json: the run's inputs, exact_median_seconds (the reference pass), and per setting the
// EvalSummary with speedup = exact_median_seconds / median_seconds; non-finite numbers as null.
nlohmann::json summaryJson(const EvalRunInfo& info, const std::vector<EvalSummary>& summaries,
                           const EvalSummary& reference);

// Median RMSE against median milliseconds per frame (log axis), a marker per setting (exact black, the
// baseline red, other surfel settings blue, simplified meshes orange and joined in order of their ratio),
// the Pareto front over all settings drawn, so one sees which family wins at which time.
Plot errorTimePlot(const std::vector<EvalSetting>& settings, const std::vector<EvalSummary>& summaries,
                   std::optional<std::size_t> baseline);

// The contact sheet's rows: the baseline between the surfel settings of lowest and highest median
// PSNR (distinct settings only, in that order); only exact when there is no surfel setting.
std::vector<std::size_t> sheetSettings(const std::vector<EvalSetting>& settings,
                                       const std::vector<EvalSummary>& summaries, std::optional<std::size_t> baseline);

}  // namespace pbs::cli
