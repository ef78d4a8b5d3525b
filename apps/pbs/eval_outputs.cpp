// Medians, the Pareto front, and the CSV, JSON and SVG texts of `pbs eval`.
#include "eval_outputs.hpp"
#include "report_numbers.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace pbs::cli {
namespace {


template <typename Field>
std::vector<double> column(const std::vector<EvalFrame>& frames, Field field) {
  std::vector<double> values;
  for (const EvalFrame& f : frames) values.push_back(field(f));
  return values;
}

nlohmann::json summaryEntry(const EvalSummary& s, double exactSeconds) {
  return {{"name", s.name},
          {"median_seconds", s.medianSeconds},
          {"median_traverse_seconds", s.medianTraverseSeconds},
          {"median_raster_seconds", s.medianRasterSeconds},
          {"median_triangles", s.medianTriangles},
          {"median_surfels", s.medianSurfels},
          {"median_rmse", s.medianRmse},
          {"worst_rmse", s.worstRmse},
          {"median_psnr", finiteOrNull(s.medianPsnr)},
          {"worst_psnr", finiteOrNull(s.worstPsnr)},
          {"median_ssim", s.medianSsim},
          {"worst_ssim", s.worstSsim},
          {"median_hole_fraction", s.medianHoleFraction},
          {"worst_hole_fraction", s.worstHoleFraction},
          {"speedup", finiteOrNull(s.medianSeconds > 0.0 ? exactSeconds / s.medianSeconds : 0.0)}};
}

}  // namespace

EvalSummary summarize(const std::string& name, const std::vector<EvalFrame>& frames) {
  EvalSummary s;
  s.name = name;
  if (frames.empty()) return s;
  const auto psnr = column(frames, [](const EvalFrame& f) { return f.error.psnr; });
  const auto ssim = column(frames, [](const EvalFrame& f) { return f.error.ssim; });
  const auto rmse = column(frames, [](const EvalFrame& f) { return f.error.rmse; });
  const auto holes = column(frames, [](const EvalFrame& f) { return f.error.holeFraction; });
  s.medianSeconds = median(column(frames, [](const EvalFrame& f) { return f.seconds; }));
  s.medianTraverseSeconds = median(column(frames, [](const EvalFrame& f) { return f.stats.traverseSeconds; }));
  s.medianRasterSeconds = median(column(frames, [](const EvalFrame& f) { return f.stats.rasterSeconds; }));
  s.medianTriangles = median(column(frames, [](const EvalFrame& f) { return double(f.stats.triangles); }));
  s.medianSurfels = median(column(frames, [](const EvalFrame& f) { return double(f.stats.surfels); }));
  s.medianRmse = median(rmse);
  s.worstRmse = *std::max_element(rmse.begin(), rmse.end());
  s.medianPsnr = median(psnr);
  s.worstPsnr = *std::min_element(psnr.begin(), psnr.end());
  s.medianSsim = median(ssim);
  s.worstSsim = *std::min_element(ssim.begin(), ssim.end());
  s.medianHoleFraction = median(holes);
  s.worstHoleFraction = *std::max_element(holes.begin(), holes.end());
  return s;
}

std::vector<std::size_t> paretoFront(const std::vector<std::pair<double, double>>& points) {
  std::vector<std::size_t> front;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto [x, y] = points[i];
    if (!std::isfinite(x) || !std::isfinite(y)) continue;
    bool beaten = false;
    for (std::size_t j = 0; j < points.size() && !beaten; ++j) {
      const auto [u, v] = points[j];
      beaten = j != i && std::isfinite(u) && std::isfinite(v) && u <= x && v <= y && (u < x || v < y);
    }
    if (!beaten) front.push_back(i);
  }
  std::stable_sort(front.begin(), front.end(), [&](std::size_t a, std::size_t b) { return points[a] < points[b]; });
  return front;
}

std::string evalCsv(const std::vector<EvalSetting>& settings, const EvalResults& results) {
  std::string csv = kEvalCsvHeader;
  csv.push_back('\n');
  for (std::size_t s = 0; s < settings.size(); ++s) {
    for (const EvalFrame& f : results.settings[s].frames)
      appendCsvLine(csv, settings[s].name,
                    {double(f.frame), f.azimuthDegrees, f.seconds, f.stats.traverseSeconds, f.stats.rasterSeconds,
                     double(f.stats.triangles), double(f.stats.surfels), f.error.rmse, f.error.psnr, f.error.ssim,
                     f.error.holeFraction});
  }
  return csv;
}

nlohmann::json summaryJson(const EvalRunInfo& info, const std::vector<EvalSummary>& summaries,
                           const EvalSummary& reference) {
  nlohmann::json json = {
      {"scene", info.scene},
      {"surfels", info.surfels},
      {"width", info.width},
      {"height", info.height},
      {"frames", info.frames},
      {"orbit", {info.orbit.azimuthDegrees, info.orbit.elevationDegrees, info.orbit.distance}},
      {"exact_median_seconds", reference.medianSeconds},
      {"baseline", info.baseline ? nlohmann::json(summaries[*info.baseline].name) : nlohmann::json()},
      {"settings", nlohmann::json::array()},
      {"pareto_front", nlohmann::json::array()},
  };
  std::vector<std::pair<double, double>> points;
  for (const EvalSummary& s : summaries) {
    json["settings"].push_back(summaryEntry(s, reference.medianSeconds));
    points.emplace_back(s.medianSeconds, s.medianRmse);
  }
  for (std::size_t i : paretoFront(points)) json["pareto_front"].push_back(summaries[i].name);
  return json;
}

Plot errorTimePlot(const std::vector<EvalSetting>& settings, const std::vector<EvalSummary>& summaries,
                   std::optional<std::size_t> baseline) {
  const std::string simplifiedColor = "#ff7f0e";
  Plot plot;
  plot.title = "Error against time (median over the orbit)";
  plot.x = PlotAxis{.label = "milliseconds per frame", .log = true, .min = {}, .max = {}};
  plot.y = PlotAxis{.label = "RMSE against exact", .log = false, .min = 0.0, .max = {}};
  std::vector<std::pair<double, double>> points;
  std::vector<std::pair<double, std::size_t>> simplified;  // (ratio, setting)
  for (std::size_t i = 0; i < summaries.size(); ++i) {
    const EvalSummary& s = summaries[i];
    points.emplace_back(s.medianSeconds * 1e3, s.medianRmse);
    if (settings[i].simplify) simplified.emplace_back(*settings[i].simplify, i);
    const std::string color = settings[i].exact      ? "black"
                              : settings[i].simplify ? simplifiedColor
                              : baseline == i        ? "#d62728"
                                                     : "#1f77b4";
    plot.markers.push_back({.x = points.back().first, .y = points.back().second, .label = s.name, .color = color});
  }
  PlotSeries front{.name = "Pareto front", .points = {}, .color = "#7f7f7f"};
  for (std::size_t i : paretoFront(points)) front.points.push_back(points[i]);
  plot.series.push_back(std::move(front));
  // A line through the simplified meshes gives them a legend entry and shows their own trade-off.
  if (!simplified.empty()) {
    std::sort(simplified.begin(), simplified.end());
    PlotSeries meshes{.name = "simplified meshes", .points = {}, .color = simplifiedColor};
    for (const auto& [ratio, i] : simplified) meshes.points.push_back(points[i]);
    plot.series.push_back(std::move(meshes));
  }
  return plot;
}

std::vector<std::size_t> sheetSettings(const std::vector<EvalSetting>& settings,
                                       const std::vector<EvalSummary>& summaries, std::optional<std::size_t> baseline) {
  std::optional<std::size_t> worst, best;
  for (std::size_t i = 0; i < settings.size(); ++i) {
    if (settings[i].exact) continue;
    if (!worst || summaries[i].medianPsnr < summaries[*worst].medianPsnr) worst = i;
    if (!best || summaries[i].medianPsnr > summaries[*best].medianPsnr) best = i;
  }
  std::vector<std::size_t> rows;
  for (const auto& candidate : {worst, baseline, best})
    if (candidate && std::find(rows.begin(), rows.end(), *candidate) == rows.end()) rows.push_back(*candidate);
  if (rows.empty())
    for (std::size_t i = 0; i < settings.size() && rows.empty(); ++i)
      if (settings[i].exact) rows.push_back(i);
  return rows;
}

}  // namespace pbs::cli
