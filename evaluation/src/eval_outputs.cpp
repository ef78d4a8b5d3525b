// Medians, worst frames, the Pareto front, and the CSV, JSON and SVG texts of `pbs eval`.
#include "pbs/evaluation/eval_outputs.hpp"

#include "pbs/evaluation/contact_sheet.hpp"
#include "pbs/evaluation/report_numbers.hpp"
#include "pbs/surfels/geometry_drawer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <tuple>

namespace pbs {
namespace {

// The frames of `result` whose view is of `kind` (all when unset).
std::vector<const EvalFrame*> framesOf(const EvalSettingResult& result, const std::vector<EvalView>& views,
                                       std::optional<FrameKind> kind) {
  std::vector<const EvalFrame*> frames;
  for (const EvalFrame& f : result.frames)
    if (!kind || views[f.frame].kind == *kind) frames.push_back(&f);
  return frames;
}

template <typename Field>
std::vector<double> column(const std::vector<const EvalFrame*>& frames, Field field) {
  std::vector<double> values;
  for (const EvalFrame* f : frames) values.push_back(field(*f));
  return values;
}

// The frame whose `field` is the largest (`largest`) or the smallest; the first such.
template <typename Field>
const EvalFrame& extreme(const std::vector<const EvalFrame*>& frames, Field field, bool largest) {
  const EvalFrame* best = frames.front();
  for (const EvalFrame* f : frames)
    if (largest ? field(*f) > field(*best) : field(*f) < field(*best)) best = f;
  return *best;
}

nlohmann::json summaryEntry(const EvalSummary& s) {
  return {{"frames", s.frames},
          {"median_seconds", s.medianSeconds},
          {"median_traverse_seconds", s.medianTraverseSeconds},
          {"median_raster_seconds", s.medianRasterSeconds},
          {"median_speedup_over_fastest_exact", s.medianSpeedup},
          {"median_triangles", s.medianTriangles},
          {"median_surfels", s.medianSurfels},
          {"median_flip", s.medianFlip},
          {"worst_flip", s.worstFlip},
          {"worst_flip_frame", s.worstFlipFrame},
          {"median_flip_mean", s.medianFlipMean},
          {"median_foreground_psnr", finiteOrNull(s.medianForegroundPsnr)},
          {"worst_foreground_psnr", finiteOrNull(s.worstForegroundPsnr)},
          {"worst_foreground_psnr_frame", s.worstForegroundPsnrFrame},
          {"median_psnr", finiteOrNull(s.medianPsnr)},
          {"median_ssim", s.medianSsim},
          {"worst_ssim", s.worstSsim},
          {"median_hole_fraction", s.medianHoleFraction},
          {"worst_hole_fraction", s.worstHoleFraction},
          {"median_bloat_fraction", s.medianBloatFraction},
          {"worst_bloat_fraction", s.worstBloatFraction}};
}

const char* kindOrAll(std::optional<FrameKind> kind) { return kind ? frameKindName(*kind) : "all"; }

}  // namespace

EvalSummary summarize(const std::string& name, const EvalSettingResult& result, const std::vector<EvalView>& views,
                      std::optional<FrameKind> kind) {
  EvalSummary s;
  s.name = name;
  const std::vector<const EvalFrame*> frames = framesOf(result, views, kind);
  s.frames = frames.size();
  if (frames.empty()) return s;
  const auto flip = [](const EvalFrame& f) { return f.error.flipForegroundMean; };
  const auto foregroundPsnr = [](const EvalFrame& f) { return f.error.foregroundPsnr; };
  const auto ssim = column(frames, [](const EvalFrame& f) { return f.error.ssim; });
  const auto holes = column(frames, [](const EvalFrame& f) { return f.error.holeFraction; });
  const auto bloat = column(frames, [](const EvalFrame& f) { return f.error.bloatFraction; });
  s.medianSeconds = median(column(frames, [](const EvalFrame& f) { return f.seconds; }));
  s.medianTraverseSeconds = median(column(frames, [](const EvalFrame& f) { return f.stats.traverseSeconds; }));
  s.medianRasterSeconds = median(column(frames, [](const EvalFrame& f) { return f.stats.rasterSeconds; }));
  s.medianSpeedup = median(column(frames, [](const EvalFrame& f) { return f.speedupOverFastestExact; }));
  s.medianTriangles = median(column(frames, [](const EvalFrame& f) { return double(f.stats.triangles); }));
  s.medianSurfels = median(column(frames, [](const EvalFrame& f) { return double(f.stats.surfels); }));
  s.medianFlip = median(column(frames, flip));
  const EvalFrame& worstFlip = extreme(frames, flip, true);
  s.worstFlip = flip(worstFlip);
  s.worstFlipFrame = worstFlip.frame;
  s.medianFlipMean = median(column(frames, [](const EvalFrame& f) { return f.error.flipMean; }));
  s.medianForegroundPsnr = median(column(frames, foregroundPsnr));
  const EvalFrame& worstPsnr = extreme(frames, foregroundPsnr, false);
  s.worstForegroundPsnr = foregroundPsnr(worstPsnr);
  s.worstForegroundPsnrFrame = worstPsnr.frame;
  s.medianPsnr = median(column(frames, [](const EvalFrame& f) { return f.error.psnr; }));
  s.medianSsim = median(ssim);
  s.worstSsim = *std::min_element(ssim.begin(), ssim.end());
  s.medianHoleFraction = median(holes);
  s.worstHoleFraction = *std::max_element(holes.begin(), holes.end());
  s.medianBloatFraction = median(bloat);
  s.worstBloatFraction = *std::max_element(bloat.begin(), bloat.end());
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
    for (const EvalFrame& f : results.settings[s].frames) {
      const EvalView& view = results.views[f.frame];
      const ImageDifference& e = f.error;
      // A surfel frame reports its own drawer; the peers and simplified meshes have one each.
      const GeometryDrawer drawer = settings[s].mode == RenderMode::Embree    ? GeometryDrawer::Rays
                                    : settings[s].mode == RenderMode::Surfels ? f.stats.geometryDrawer
                                                                              : GeometryDrawer::Raster;
      appendCsvLine(csv,
                    settings[s].name + "," + std::to_string(f.frame) + "," + frameKindName(view.kind) + "," +
                        geometryDrawerName(drawer),
                    {view.geometryShare, f.seconds, f.speedupOverFastestExact, f.stats.traverseSeconds,
                     f.stats.rasterSeconds, double(f.stats.triangles), double(f.stats.surfels), e.flipForegroundMean,
                     e.flipMean, e.flipMedian, e.flipMax, e.foregroundPsnr, e.psnr, e.ssim, e.holeFraction,
                     e.bloatFraction, f.surfelLoadSeconds, f.divisor, f.bvhBuildSeconds});
    }
  }
  return csv;
}

nlohmann::json evalSummaryJson(const EvalRunInfo& info, const std::vector<EvalSetting>& settings,
                               const EvalResults& results) {
  std::vector<double> referenceSeconds;
  double surfelReadSeconds = 0.0;  // by the frames, as they drew prefixes not read before
  for (const EvalSettingResult& setting : results.settings)
    for (const EvalFrame& frame : setting.frames) surfelReadSeconds += frame.surfelLoadSeconds;
  nlohmann::json kinds = nlohmann::json::array();
  for (const EvalView& view : results.views) {
    referenceSeconds.push_back(view.referenceSeconds);
    kinds.push_back({{"kind", frameKindName(view.kind)}, {"geometry_share", view.geometryShare}});
  }
  nlohmann::json json = {
      {"scene", info.scene},
      {"surfels", info.surfels},
      {"path", info.path},
      {"width", info.width},
      {"height", info.height},
      {"frames", info.frames},
      {"reference",
       {{"renderer", info.referenceRenderer},
        {"samples", info.referenceSamples},
        {"median_seconds", median(referenceSeconds)}}},
      {"meshes", info.meshesOnDemand ? "read as frames draw them" : "read whole"},
      {"load_seconds", info.loadSeconds},
      {"surfels_load_seconds", info.surfelsLoadSeconds},
      {"surfels_read_seconds", surfelReadSeconds},
      {"surfel_bytes_read", info.surfelBytesRead},
      {"embree_build_seconds", results.buildSeconds},
      {"frame_kinds", kinds},
      {"baseline", settings[info.baseline].name},
      {"settings", nlohmann::json::array()},
      {"pareto_front", nlohmann::json::array()},
  };
  std::vector<std::pair<double, double>> points;
  for (std::size_t s = 0; s < settings.size(); ++s) {
    nlohmann::json entry = {{"name", settings[s].name}};
    for (std::optional<FrameKind> kind : {std::optional<FrameKind>(), std::optional(FrameKind::Near),
                                          std::optional(FrameKind::Mid), std::optional(FrameKind::Far)}) {
      const EvalSummary summary = summarize(settings[s].name, results.settings[s], results.views, kind);
      if (summary.frames > 0) entry[kindOrAll(kind)] = summaryEntry(summary);
      if (!kind) points.emplace_back(summary.medianSeconds, summary.medianFlip);
    }
    json["settings"].push_back(std::move(entry));
  }
  for (std::size_t i : paretoFront(points)) json["pareto_front"].push_back(settings[i].name);
  return json;
}

Plot errorTimePlot(const std::vector<EvalSetting>& settings, const std::vector<EvalSummary>& summaries,
                   std::size_t baseline) {
  const std::string simplifiedColor = "#ff7f0e";
  Plot plot;
  plot.title = "FLIP against time (medians over the path; reference: Embree, many samples)";
  plot.x = PlotAxis{.label = "milliseconds per frame", .log = true, .min = {}, .max = {}};
  plot.y = PlotAxis{.label = "FLIP over the foreground (lower is better)", .log = true, .min = {}, .max = {}};
  std::vector<std::pair<double, double>> points;
  std::vector<std::pair<double, std::size_t>> simplified, embree;  // (ratio or samples, setting)
  for (std::size_t i = 0; i < summaries.size(); ++i) {
    const EvalSummary& s = summaries[i];
    const EvalSetting& setting = settings[i];
    points.emplace_back(s.medianSeconds * 1e3, s.medianFlip);
    if (setting.simplify) simplified.emplace_back(*setting.simplify, i);
    if (setting.mode == RenderMode::Embree) embree.emplace_back(double(setting.samples), i);
    const std::string color = setting.isPeer()   ? "black"
                              : setting.simplify ? simplifiedColor
                              : baseline == i    ? "#d62728"
                                                 : "#1f77b4";
    plot.markers.push_back({.x = points.back().first, .y = points.back().second, .label = s.name, .color = color});
  }
  PlotSeries front{.name = "Pareto front", .points = {}, .color = "#7f7f7f"};
  for (std::size_t i : paretoFront(points)) front.points.push_back(points[i]);
  plot.series.push_back(std::move(front));
  // Lines through Embree's sample counts and the simplified meshes give them legend entries and show
  // their own trade-offs.
  for (auto [list, name, color] : {std::tuple(&embree, "Embree rays, 1-16 samples", std::string("black")),
                                   std::tuple(&simplified, "simplified meshes", simplifiedColor)}) {
    if (list->empty()) continue;
    std::sort(list->begin(), list->end());
    PlotSeries series{.name = name, .points = {}, .color = color};
    for (const auto& [order, i] : *list) series.points.push_back(points[i]);
    plot.series.push_back(std::move(series));
  }
  return plot;
}

std::vector<std::size_t> sheetSettings(const std::vector<EvalSetting>& settings,
                                       const std::vector<EvalSummary>& summaries, std::size_t baseline) {
  std::optional<std::size_t> worst, best, rays;
  for (std::size_t i = 0; i < settings.size(); ++i) {
    if (settings[i].mode == RenderMode::Embree && settings[i].samples == 1) rays = i;
    if (settings[i].isPeer()) continue;
    if (!worst || summaries[i].medianFlip > summaries[*worst].medianFlip) worst = i;
    if (!best || summaries[i].medianFlip < summaries[*best].medianFlip) best = i;
  }
  std::vector<std::size_t> rows;
  for (const auto& candidate : {worst, std::optional(baseline), best, rays})
    if (candidate && std::find(rows.begin(), rows.end(), *candidate) == rows.end()) rows.push_back(*candidate);
  return rows;
}

EvalFiles evalFiles(const EvalRunInfo& info, const std::vector<EvalSetting>& settings, const EvalResults& results,
                    std::uint32_t sheetFrame, const glm::vec3& background) {
  EvalFiles files;
  for (std::size_t s = 0; s < settings.size(); ++s)
    files.summaries.push_back(summarize(settings[s].name, results.settings[s], results.views));
  files.csv = evalCsv(settings, results);
  files.summary = evalSummaryJson(info, settings, results);
  files.plot = renderSvg(errorTimePlot(settings, files.summaries, info.baseline));

  const std::vector<std::size_t> rows = sheetSettings(settings, files.summaries, info.baseline);
  std::vector<std::span<const std::uint8_t>> tiles;
  for (std::size_t s : rows) {
    tiles.emplace_back(results.referenceSheet);
    tiles.emplace_back(results.settings[s].sheetImage);
    tiles.emplace_back(results.settings[s].sheetFlip);
    files.summary["contact_sheet"]["rows"].push_back(settings[s].name);
  }
  files.summary["contact_sheet"]["file"] = "contact_sheet.png";
  files.summary["contact_sheet"]["frame"] = sheetFrame;
  const std::uint8_t rgb[3] = {std::uint8_t(std::lround(background.r * 255.0f)),
                               std::uint8_t(std::lround(background.g * 255.0f)),
                               std::uint8_t(std::lround(background.b * 255.0f))};
  files.sheetWidth = 3 * info.width;
  files.sheetHeight = std::uint32_t(rows.size()) * info.height;
  files.sheet = contactSheet(info.width, info.height, 3, tiles, rgb);
  return files;
}

}  // namespace pbs
