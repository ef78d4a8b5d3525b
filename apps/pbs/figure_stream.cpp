// The stream figure: one view, its reference, then per bandwidth and order a fresh cache and link whose
// clock steps through the plotted time, each step's frame compared with the reference.
#include "figure_stream.hpp"

#include <pbs/evaluation/contact_sheet.hpp>
#include "image_files.hpp"
#include "progress_meter.hpp"
#include <pbs/evaluation/report_numbers.hpp>
#include "scene_report.hpp"
#include <pbs/evaluation/svg_plot.hpp>

#include <pbs/raster/headlight_shading.hpp>
#include <pbs/raster/image_metrics.hpp>
#include <pbs/surfels/frame_renderer.hpp>
#include <pbs/surfels/surfel_stream.hpp>

#include <algorithm>
#include <cstdio>
#include <span>
#include <stdexcept>

namespace pbs::cli {
namespace {

constexpr std::uint64_t kCacheBytes = std::uint64_t(1) << 30;
constexpr std::array<StreamOrder, 2> kOrders = {StreamOrder::Prefixes, StreamOrder::WholeArrays};

struct StreamStep {
  double seconds = 0.0;
  std::uint64_t bytes = 0;
  std::uint64_t missingBytes = 0;
  LodStats stats;
  ImageDifference error;
  std::vector<std::uint8_t> image;  // RGBA8, kept for the sheet's steps only
};

struct StreamSeries {
  double megabytesPerSecond = 0.0;
  StreamOrder order = StreamOrder::Prefixes;
  std::vector<StreamStep> steps;
};

// The steps whose frames the sheet shows: a quarter, half and all of the time.
std::array<std::uint32_t, 3> sheetSteps(std::uint32_t steps) {
  return {std::max(1u, steps / 4) - 1, std::max(1u, steps / 2) - 1, steps - 1};
}

std::string seriesName(const StreamSeries& s) {
  char name[64];
  std::snprintf(name, sizeof name, "%g MB/s, %s", s.megabytesPerSecond,
                s.order == StreamOrder::Prefixes ? "prefixes" : "whole arrays");
  return name;
}

StreamSeries streamSeries(const LoadedScene& loaded, const StreamFigureOptions& options, const Camera& camera,
                          const RgbaImage& reference, double megabytesPerSecond, StreamOrder order,
                          const std::function<void(std::uint32_t)>& onStep) {
  SurfelCache cache(options.surfels, loaded.scene, loaded.hierarchy, kCacheBytes);
  SurfelStream stream(cache, loaded.scene, loaded.hierarchy, options.lod,
                      {.bytesPerSecond = megabytesPerSecond * 1e6, .order = order});
  // The steps share the mesh BVHs that rays build, as a path's frames do.
  LodOptions lod = options.lod;
  lod.bvhBuildFrames = double(options.steps);
  FrameRenderer renderer(loaded.scene, loaded.hierarchy, {.mode = RenderMode::Surfels, .lod = lod}, options.width,
                         options.height, {.cache = &cache, .stream = &stream});
  const auto shown = sheetSteps(options.steps);
  StreamSeries series{megabytesPerSecond, order, {}};
  for (std::uint32_t i = 0; i < options.steps; ++i) {
    stream.advance(camera, options.seconds / options.steps);
    FrameResult frame = renderer.render(camera);
    StreamStep step{.seconds = stream.stats().seconds,
                    .bytes = stream.stats().bytes,
                    .missingBytes = stream.stats().missingBytes,
                    .stats = frame.stats,
                    .error = {},
                    .image = {}};
    if (std::find(shown.begin(), shown.end(), i) != shown.end()) step.image = toRgba8(frame.image);
    step.error = compareImages(RgbaImage{options.width, options.height, std::move(frame.image)}, reference);
    series.steps.push_back(std::move(step));
    onStep(i);
  }
  return series;
}

std::string streamCsv(const std::vector<StreamSeries>& all) {
  std::string csv =
      "order,megabytes_per_second,seconds,bytes,missing_bytes,surfels,triangles,flip_foreground,psnr_foreground,"
      "hole_fraction,bloat_fraction\n";
  for (const StreamSeries& s : all)
    for (const StreamStep& step : s.steps)
      appendCsvLine(csv, streamOrderName(s.order),
                    {s.megabytesPerSecond, step.seconds, double(step.bytes), double(step.missingBytes),
                     double(step.stats.surfels), double(step.stats.triangles), step.error.flipForegroundMean,
                     step.error.foregroundPsnr, step.error.holeFraction, step.error.bloatFraction});
  return csv;
}

nlohmann::json streamJson(const StreamFigureOptions& options, const std::string& scene,
                          const std::vector<StreamSeries>& all, const ImageDifference& loadedError) {
  nlohmann::json json = {
      {"figure", "stream"},
      {"scene", scene},
      {"surfels", options.surfels},
      {"width", options.width},
      {"height", options.height},
      {"orbit", {options.orbit.azimuthDegrees, options.orbit.elevationDegrees, options.orbit.distance}},
      {"reference_samples", options.referenceSamples},
      {"every_prefix_loaded",
       {{"flip_foreground", loadedError.flipForegroundMean},
        {"psnr_foreground", finiteOrNull(loadedError.foregroundPsnr)}}},
      {"series", nlohmann::json::array()}};
  for (const StreamSeries& s : all) {
    nlohmann::json steps = nlohmann::json::array();
    for (const StreamStep& step : s.steps)
      steps.push_back({{"seconds", step.seconds},
                       {"bytes", step.bytes},
                       {"missing_bytes", step.missingBytes},
                       {"surfels", step.stats.surfels},
                       {"triangles", step.stats.triangles},
                       {"flip_foreground", step.error.flipForegroundMean},
                       {"psnr_foreground", finiteOrNull(step.error.foregroundPsnr)},
                       {"hole_fraction", step.error.holeFraction},
                       {"bloat_fraction", step.error.bloatFraction}});
    json["series"].push_back(
        {{"megabytes_per_second", s.megabytesPerSecond}, {"order", streamOrderName(s.order)}, {"steps", steps}});
  }
  return json;
}

std::string streamSvg(const StreamFigureOptions& options, const std::string& scene,
                      const std::vector<StreamSeries>& all, double loadedFlip) {
  Plot plot;
  plot.title = scene + ": FLIP while the surfels stream in, against the " + std::to_string(options.referenceSamples) +
               "-sample reference";
  plot.x = {.label = "seconds (simulated link)", .log = false, .min = 0.0, .max = options.seconds};
  plot.y = {.label = "FLIP over covered pixels", .log = false, .min = 0.0, .max = std::nullopt};
  for (const StreamSeries& s : all) {
    PlotSeries series{seriesName(s), {}, ""};
    for (const StreamStep& step : s.steps) series.points.emplace_back(step.seconds, step.error.flipForegroundMean);
    plot.series.push_back(std::move(series));
  }
  plot.series.push_back({"every prefix loaded", {{0.0, loadedFlip}, {options.seconds, loadedFlip}}, "#888888"});
  return renderSvg(plot);
}

}  // namespace

void writeStreamFigure(const StreamFigureOptions& options, const std::filesystem::path& folder) {
  if (options.bandwidths.empty()) throw std::invalid_argument("the stream figure needs a bandwidth");
  SurfelFileReader file(options.surfels);  // the hierarchy it was made of: the scene's own, or its loose octree
  const LoadedScene loaded = loadAndAnalyze(options.scene, LoadOptions{}, file);
  const Bounds& bounds = loaded.summary.bounds;
  const Camera camera =
      orbitCamera(bounds.center(), 0.5 * glm::length(bounds.size()), options.orbit, options.width, options.height);
  std::filesystem::create_directories(folder);

  ProgressMeter meter("stream", ProgressMeter::styleFor(options.quiet));
  meter.update(0.0, "reference");
  FrameResult referenceFrame =
      FrameRenderer(loaded.scene, loaded.hierarchy, {.mode = RenderMode::Embree, .samples = options.referenceSamples},
                    options.width, options.height)
          .render(camera);
  const std::vector<std::uint8_t> referenceTile = toRgba8(referenceFrame.image);
  const RgbaImage reference{options.width, options.height, std::move(referenceFrame.image)};

  // The level the streams converge to: every prefix the view draws read at once.
  SurfelCache wholeCache(options.surfels, loaded.scene, loaded.hierarchy, kCacheBytes);
  FrameResult whole = FrameRenderer(loaded.scene, loaded.hierarchy, {.mode = RenderMode::Surfels, .lod = options.lod},
                                    options.width, options.height, {.cache = &wholeCache})
                          .render(camera);
  const ImageDifference loadedError =
      compareImages(RgbaImage{options.width, options.height, std::move(whole.image)}, reference);

  std::vector<double> bandwidths = options.bandwidths;
  std::sort(bandwidths.begin(), bandwidths.end());
  std::vector<StreamSeries> all;
  const double total = double(bandwidths.size() * kOrders.size() * options.steps);
  for (double megabytesPerSecond : bandwidths)
    for (StreamOrder order : kOrders) {
      const double done = double(all.size() * options.steps);
      all.push_back(streamSeries(loaded, options, camera, reference, megabytesPerSecond, order, [&](std::uint32_t i) {
        meter.update((done + i + 1) / total,
                     std::to_string(std::size_t(done) + i + 1) + "/" + std::to_string(std::size_t(total)) + " frames");
      }));
    }
  meter.finish(std::to_string(all.size()) + " series of " + std::to_string(options.steps) + " frames");

  // The sheet: the lowest bandwidth's two orders beside the reference, at the shown steps.
  std::vector<std::span<const std::uint8_t>> tiles;
  for (std::uint32_t step : sheetSteps(options.steps)) {
    tiles.push_back(all[0].steps[step].image);
    tiles.push_back(all[1].steps[step].image);
    tiles.push_back(referenceTile);
  }
  const std::uint8_t background[3] = {235, 235, 235};
  writeImage8(folder / "stream.png", 3 * options.width, 3 * options.height, 3,
              contactSheet(options.width, options.height, 3, tiles, background));
  writeTextFile(folder / "stream.csv", streamCsv(all));
  writeTextFile(folder / "stream.json", streamJson(options, loaded.name, all, loadedError).dump(2) + "\n");
  writeTextFile(folder / "stream.svg", streamSvg(options, loaded.name, all, loadedError.flipForegroundMean));

  std::printf("%s: %ux%u; every prefix loaded: FLIP %.4f\n", loaded.name.c_str(), options.width, options.height,
              loadedError.flipForegroundMean);
  std::printf("%-26s %10s %10s %10s %10s %12s\n", "series", "FLIP 1/4", "FLIP 1/2", "FLIP end", "MB by end",
              "missing MB");
  const auto shown = sheetSteps(options.steps);
  for (const StreamSeries& s : all)
    std::printf("%-26s %10.4f %10.4f %10.4f %10.1f %12.1f\n", seriesName(s).c_str(),
                s.steps[shown[0]].error.flipForegroundMean, s.steps[shown[1]].error.flipForegroundMean,
                s.steps[shown[2]].error.flipForegroundMean, s.steps.back().bytes / 1e6,
                s.steps.back().missingBytes / 1e6);
  std::printf("wrote %s/{stream.svg, stream.png, stream.csv, stream.json}\n", folder.string().c_str());
}

}  // namespace pbs::cli
