// What `pbs eval` writes: eval.csv (one row per setting and frame), summary.json (medians and worst
// frames per setting, over all frames and per frame kind), error_vs_time.svg (FLIP against time, a
// marker per setting, the Embree curve and the Pareto front drawn).
#pragma once

#include "pbs/evaluation/eval_run.hpp"
#include "pbs/evaluation/eval_settings.hpp"
#include "pbs/evaluation/svg_plot.hpp"

#include <pbs/surfels/frame_kind.hpp>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace pbs {

// The CSV header, in column order. "geometry" is what drew the frame's geometry: "rays" (Embree, or a
// surfel frame's geometry nodes by rays) or "raster" (the rasterizer, which also stands for none). "flip" is
// FLIP's mean over the foreground (the pixels either image covers), the error every summary and plot reads;
// flip_mean over the whole image as NVIDIA's tool reports it.
inline constexpr const char* kEvalCsvHeader =
    "setting,frame,kind,geometry,geometry_share,seconds,speedup,traverse_seconds,raster_seconds,triangles,surfels,flip,"
    "flip_mean,flip_median,flip_max,foreground_psnr,psnr,ssim,hole_fraction,bloat_fraction,surfel_load_seconds,"
    "resolution_divisor,bvh_build_seconds";

// Medians and worst frames of one setting over a set of frames (all, or those of one kind).
struct EvalSummary {
  std::string name;
  std::size_t frames = 0;
  double medianSeconds = 0.0, medianTraverseSeconds = 0.0, medianRasterSeconds = 0.0;
  double medianSpeedup = 0.0;  // over the fastest exact peer, frame by frame
  double medianTriangles = 0.0, medianSurfels = 0.0;
  double medianFlip = 0.0, worstFlip = 0.0;  // foreground FLIP; worst: largest
  std::uint32_t worstFlipFrame = 0;
  double medianFlipMean = 0.0;                                   // whole-image FLIP
  double medianForegroundPsnr = 0.0, worstForegroundPsnr = 0.0;  // worst: smallest; +inf when identical
  std::uint32_t worstForegroundPsnrFrame = 0;
  double medianPsnr = 0.0;
  double medianSsim = 1.0, worstSsim = 1.0;
  double medianHoleFraction = 0.0, worstHoleFraction = 0.0;
  double medianBloatFraction = 0.0, worstBloatFraction = 0.0;
};

// Over `frames` of `result` whose view kind is `kind` (all of them when unset); frames = 0 when none.
EvalSummary summarize(const std::string& name, const EvalSettingResult& result, const std::vector<EvalView>& views,
                      std::optional<FrameKind> kind = std::nullopt);

// Indices of the points no other point beats in both coordinates (smaller x and smaller y, at least
// one strictly), sorted by x: the settings worth choosing when both time and error count.
std::vector<std::size_t> paretoFront(const std::vector<std::pair<double, double>>& points);

// Rows in setting order, frames in order; psnr is written "inf" for identical images.
std::string evalCsv(const std::vector<EvalSetting>& settings, const EvalResults& results);

struct EvalRunInfo {
  std::string scene;
  std::string surfels;  // the .surfels file
  std::string path;     // the camera path's name
  std::uint32_t width = 0, height = 0, frames = 0;
  std::string referenceRenderer;  // "embree" or "exact"
  std::uint32_t referenceSamples = 0;
  bool meshesOnDemand = false;        // the scene opened without its mesh arrays
  std::size_t baseline = 0;           // index into the settings
  double loadSeconds = 0.0;           // the scene file
  double surfelsLoadSeconds = 0.0;    // opening the .surfels file (its tables); frames read their prefixes
  std::uint64_t surfelBytesRead = 0;  // of the .surfels file, by opening it and by every frame
};

// summary.json: the run's inputs, the reference's and the BVH's times, the frame kinds, and per setting
// its summary over all frames and per kind; non-finite numbers as null.
nlohmann::json evalSummaryJson(const EvalRunInfo& info, const std::vector<EvalSetting>& settings,
                               const EvalResults& results);

// Median foreground FLIP against median milliseconds per frame (both log axes), a marker per setting
// (peers black, the baseline red, other surfel settings blue, simplified meshes orange), Embree's
// samples joined into its curve, the simplified meshes joined in order of their ratio, and the Pareto
// front over all settings.
Plot errorTimePlot(const std::vector<EvalSetting>& settings, const std::vector<EvalSummary>& summaries,
                   std::size_t baseline);

// The contact sheet's rows: the baseline between the surfel or simplified settings of highest and
// lowest median FLIP, then the 1-sample Embree peer (distinct settings only).
std::vector<std::size_t> sheetSettings(const std::vector<EvalSetting>& settings,
                                       const std::vector<EvalSummary>& summaries, std::size_t baseline);

// Every file of an evaluation, made in memory: what `pbs eval` writes into its folder.
struct EvalFiles {
  std::vector<EvalSummary> summaries;  // per setting, over all its frames
  std::string csv;                     // eval.csv
  nlohmann::json summary;              // summary.json, with the contact sheet's rows, file and frame
  std::string plot;                    // error_vs_time.svg
  // contact_sheet.png as RGB8, reference | setting | FLIP map for each setting sheetSettings picks, of the
  // frame `sheetFrame` (EvalInputs::sheetFrame), composited over `background`.
  std::vector<std::uint8_t> sheet;
  std::uint32_t sheetWidth = 0, sheetHeight = 0;
};
EvalFiles evalFiles(const EvalRunInfo& info, const std::vector<EvalSetting>& settings, const EvalResults& results,
                    std::uint32_t sheetFrame, const glm::vec3& background);

}  // namespace pbs
