// The scaling figure: cities of growing size, each measured in both modes over the same orbit, then
// written as CSV, JSON and a log-log plot.
#include "figure_scaling.hpp"

#include <pbs/evaluation/mode_comparison.hpp>
#include "orbit_views.hpp"
#include "progress_meter.hpp"
#include <pbs/evaluation/report_numbers.hpp>
#include "scene_report.hpp"
#include <pbs/evaluation/svg_plot.hpp>

#include <pbs/scene/generate.hpp>
#include <pbs/scene/load_scene.hpp>

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace pbs::cli {
namespace {

// One city of the series; frame values are medians over the orbit's frames.
struct ScalingPoint {
  std::uint32_t levels = 0;
  std::uint64_t triangles = 0, instances = 0;
  double surfelizeSeconds = 0.0;
  std::uint64_t surfelsMade = 0;                    // over all arrays surfelize made
  double exactMs = 0.0, surfelsMs = 0.0;            // whole frames
  double surfelsDrawn = 0.0, trianglesDrawn = 0.0;  // surfels mode
  double exactTrianglesDrawn = 0.0;
  double psnr = 0.0, ssim = 0.0;  // surfels against exact
};

constexpr const char* kScalingCsvHeader =
    "triangles,instances,levels,fanout,surfelize_seconds,surfels_made,exact_ms,surfels_ms,surfels_drawn,"
    "triangles_drawn,exact_triangles_drawn,psnr,ssim";

ScalingPoint measureCity(const Scene& city, const Hierarchy& hierarchy, const SceneSummary& summary,
                         std::uint32_t levels, const ScalingOptions& options) {
  const std::string name = withThousands(summary.triangles) + " triangles";
  const MadeSurfels made =
      surfelizeInMemory(city, hierarchy, SurfelizeOptions{}, "surfelize " + name, progressMeters(options.quiet));
  ModeComparison modes(city, hierarchy, made.surfels, options.lod, options.width, options.height);
  const std::vector<PathView> views =
      cameraPath(options.path, hierarchy, city.roots, Orbit{}, options.frames, options.width, options.height);

  ProgressMeter meter("render " + name, ProgressMeter::styleFor(options.quiet));
  std::vector<double> exactMs, surfelsMs, surfelsDrawn, trianglesDrawn, exactTriangles, psnr, ssim;
  std::vector<Camera> cameras;
  for (const PathView& view : views) cameras.push_back(view.camera);
  const std::vector<ModeFrames> rendered = modes.render(cameras, [&](std::size_t done, std::size_t total) {
    meter.update(double(done) / double(total), "frame " + std::to_string(done) + "/" + std::to_string(total));
  });
  for (const ModeFrames& frames : rendered) {
    exactMs.push_back(frames.exact.seconds * 1e3);
    surfelsMs.push_back(frames.surfels.seconds * 1e3);
    surfelsDrawn.push_back(double(frames.surfels.stats.surfels));
    trianglesDrawn.push_back(double(frames.surfels.stats.triangles));
    exactTriangles.push_back(double(frames.exact.stats.triangles));
    psnr.push_back(frames.error.psnr);
    ssim.push_back(frames.error.ssim);
  }
  meter.finish(std::to_string(views.size()) + " frames in each mode");
  return {.levels = levels,
          .triangles = summary.triangles,
          .instances = summary.instances,
          .surfelizeSeconds = made.seconds,
          .surfelsMade = made.stats.surfels,
          .exactMs = median(exactMs),
          .surfelsMs = median(surfelsMs),
          .surfelsDrawn = median(surfelsDrawn),
          .trianglesDrawn = median(trianglesDrawn),
          .exactTrianglesDrawn = median(exactTriangles),
          .psnr = median(psnr),
          .ssim = median(ssim)};
}

std::string scalingCsv(const std::vector<ScalingPoint>& points) {
  std::string csv = std::string(kScalingCsvHeader) + "\n";
  for (const ScalingPoint& p : points)
    appendCsvLine(
        csv, csvNumber(double(p.triangles)),
        {double(p.instances), double(p.levels), double(kScalingFanout), p.surfelizeSeconds, double(p.surfelsMade),
         p.exactMs, p.surfelsMs, p.surfelsDrawn, p.trianglesDrawn, p.exactTrianglesDrawn, p.psnr, p.ssim});
  return csv;
}

nlohmann::json scalingJson(const ScalingOptions& options, const std::vector<ScalingPoint>& points) {
  const Orbit orbit;
  nlohmann::json json = {
      {"figure", "scaling"},
      {"meshes", options.meshes},
      {"fanout", kScalingFanout},
      {"width", options.width},
      {"height", options.height},
      {"frames", options.frames},
      {"orbit",
       {{"azimuth", orbit.azimuthDegrees}, {"elevation", orbit.elevationDegrees}, {"distance", orbit.distance}}},
      {"cities", nlohmann::json::array()}};
  for (const ScalingPoint& p : points)
    json["cities"].push_back({{"triangles", p.triangles},
                              {"instances", p.instances},
                              {"levels", p.levels},
                              {"surfelize_seconds", p.surfelizeSeconds},
                              {"surfels_made", p.surfelsMade},
                              {"exact_median_ms", p.exactMs},
                              {"surfels_median_ms", p.surfelsMs},
                              {"speedup", finiteOrNull(p.exactMs / p.surfelsMs)},
                              {"surfels_drawn", p.surfelsDrawn},
                              {"triangles_drawn", p.trianglesDrawn},
                              {"exact_triangles_drawn", p.exactTrianglesDrawn},
                              {"psnr_median", finiteOrNull(p.psnr)},
                              {"ssim_median", p.ssim}});
  return json;
}

Plot scalingPlot(const ScalingOptions& options, const std::vector<ScalingPoint>& points) {
  Plot plot;
  plot.title = "Frame time against scene size (" + std::to_string(options.width) + "×" +
               std::to_string(options.height) + ", median of " + std::to_string(options.frames) + " orbit frames)";
  plot.x.label = "scene triangles (instanced)";
  plot.y.label = "ms per frame";
  plot.x.log = plot.y.log = true;
  PlotSeries exact{.name = "exact", .points = {}, .color = ""};
  PlotSeries surfels{.name = "surfels", .points = {}, .color = ""};
  for (const ScalingPoint& p : points) {
    exact.points.emplace_back(double(p.triangles), p.exactMs);
    surfels.points.emplace_back(double(p.triangles), p.surfelsMs);
  }
  plot.series = {exact, surfels};
  return plot;
}

void printRow(const ScalingPoint& p) {
  std::printf("%15s %8s %10.1f %11.1f %11.1f %8.1fx %12s %12s %7.2f %7.4f\n", withThousands(p.triangles).c_str(),
              withThousands(p.instances).c_str(), p.surfelizeSeconds, p.exactMs, p.surfelsMs,
              p.exactMs / std::max(p.surfelsMs, 1e-9), withThousands(std::uint64_t(p.surfelsDrawn)).c_str(),
              withThousands(std::uint64_t(p.trianglesDrawn)).c_str(), p.psnr, p.ssim);
  std::fflush(stdout);  // a row per city as it is done: the largest take minutes
}

}  // namespace

void writeScalingFigure(const ScalingOptions& options, const std::filesystem::path& folder) {
  std::vector<Scene> prototypes;
  for (const std::string& mesh : options.meshes) prototypes.push_back(loadScene(mesh).scene);
  std::filesystem::create_directories(folder);

  std::printf("%15s %8s %10s %11s %11s %9s %12s %12s %7s %7s\n", "triangles", "inst.", "surfelize s", "exact ms",
              "surfels ms", "speed-up", "surfels", "triangles", "PSNR", "SSIM");
  std::vector<ScalingPoint> points;
  for (std::uint32_t levels = 1; levels <= kScalingMaxLevels; ++levels) {
    const Scene city = generateCity(prototypes, CityOptions{.levels = levels, .fanout = kScalingFanout});
    const Hierarchy hierarchy = analyzeHierarchy(city);
    const SceneSummary summary = summarizeScene(city, hierarchy);
    if (summary.triangles > options.maxTriangles) {
      if (points.empty())
        throw std::runtime_error("the smallest city has " + withThousands(summary.triangles) +
                                 " triangles, more than --max-triangles " + withThousands(options.maxTriangles));
      break;
    }
    points.push_back(measureCity(city, hierarchy, summary, levels, options));
    printRow(points.back());
  }

  writeTextFile(folder / "scaling.csv", scalingCsv(points));
  writeTextFile(folder / "scaling.json", scalingJson(options, points).dump(2) + "\n");
  writeTextFile(folder / "scaling.svg", renderSvg(scalingPlot(options, points)));
  std::printf("wrote %s/{scaling.csv, scaling.json, scaling.svg}\n", folder.string().c_str());
}

}  // namespace pbs::cli
