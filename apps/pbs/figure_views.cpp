// The views figure: three distances along one direction, each measured in both modes, then a contact
// sheet, CSV and JSON.
#include "figure_views.hpp"

#include <pbs/evaluation/contact_sheet.hpp>
#include <pbs/evaluation/mode_comparison.hpp>
#include "image_files.hpp"
#include "progress_meter.hpp"
#include <pbs/evaluation/report_numbers.hpp>
#include "scene_report.hpp"
#include <pbs/evaluation/svg_plot.hpp>

#include <pbs/raster/headlight_shading.hpp>
#include <pbs/raster/orbit_camera.hpp>

#include <cstdio>
#include <optional>
#include <span>
#include <vector>

namespace pbs::cli {
namespace {

constexpr std::array<const char*, 3> kViewNames = {"near", "middle", "far"};

constexpr const char* kViewsCsvHeader =
    "view,distance,exact_ms,surfels_ms,surfels_drawn,triangles_drawn,exact_triangles_drawn,geometry_nodes,"
    "surfel_nodes,psnr,ssim,hole_fraction";

struct ViewRow {
  const char* name = "";
  double distance = 0.0;  // bounding radii
  double exactMs = 0.0, surfelsMs = 0.0;
  LodStats surfelsStats;  // counts of the surfels-mode frame
  std::uint64_t exactTriangles = 0;
  ImageDifference error;  // surfels against exact
};

std::string viewsCsv(const std::vector<ViewRow>& rows) {
  std::string csv = std::string(kViewsCsvHeader) + "\n";
  for (const ViewRow& r : rows)
    appendCsvLine(csv, r.name,
                  {r.distance, r.exactMs, r.surfelsMs, double(r.surfelsStats.surfels), double(r.surfelsStats.triangles),
                   double(r.exactTriangles), double(r.surfelsStats.nodesGeometry), double(r.surfelsStats.nodesSurfels),
                   r.error.psnr, r.error.ssim, r.error.holeFraction});
  return csv;
}

nlohmann::json viewsJson(const ViewsOptions& options, const std::string& scene, const std::vector<ViewRow>& rows) {
  nlohmann::json json = {{"figure", "views"},
                         {"scene", scene},
                         {"surfels", options.surfels.empty() ? "made in memory, capture resolution " +
                                                                   std::to_string(options.surfelize.file.resolution)
                                                             : options.surfels},
                         {"width", options.width},
                         {"height", options.height},
                         {"azimuth", options.direction[0]},
                         {"elevation", options.direction[1]},
                         {"sheet",
                          {{"file", "views.png"},
                           {"rows", kViewNames},
                           {"columns", {"exact", "surfels", "difference"}},
                           {"difference_gain", kDifferenceGain}}},
                         {"views", nlohmann::json::array()}};
  for (const ViewRow& r : rows)
    json["views"].push_back({{"view", r.name},
                             {"distance", r.distance},
                             {"exact_ms", r.exactMs},
                             {"surfels_ms", r.surfelsMs},
                             {"surfels_drawn", r.surfelsStats.surfels},
                             {"triangles_drawn", r.surfelsStats.triangles},
                             {"exact_triangles_drawn", r.exactTriangles},
                             {"geometry_nodes", r.surfelsStats.nodesGeometry},
                             {"surfel_nodes", r.surfelsStats.nodesSurfels},
                             {"psnr", finiteOrNull(r.error.psnr)},
                             {"ssim", r.error.ssim},
                             {"hole_fraction", r.error.holeFraction}});
  return json;
}

SceneSurfels surfelsFor(const ViewsOptions& options, const LoadedScene& loaded) {
  if (!options.surfels.empty()) return loadSceneSurfels(options.surfels, loaded.scene, loaded.hierarchy);
  return surfelizeInMemory(loaded.scene, loaded.hierarchy, options.surfelize, "surfelize",
                           progressMeters(options.quiet))
      .surfels;
}

}  // namespace

void writeViewsFigure(const ViewsOptions& options, const std::filesystem::path& folder) {
  // With a .surfels file, the hierarchy it was made of (the scene's own, or its loose octree).
  std::optional<SurfelFileReader> file;
  if (!options.surfels.empty()) file.emplace(options.surfels);
  const LoadedScene loaded =
      file ? loadAndAnalyze(options.scene, LoadOptions{}, *file) : loadAndAnalyze(options.scene, LoadOptions{});
  const SceneSurfels surfels = surfelsFor(options, loaded);
  std::filesystem::create_directories(folder);
  ModeComparison modes(loaded.scene, loaded.hierarchy, surfels, options.lod, options.width, options.height);
  const Bounds& bounds = loaded.summary.bounds;

  ProgressMeter meter("render", ProgressMeter::styleFor(options.quiet));
  std::vector<ViewRow> rows;
  std::vector<std::vector<std::uint8_t>> tiles;  // exact, surfels, difference per view
  std::vector<Camera> cameras;
  for (double distance : options.distances)
    cameras.push_back(orbitCamera(bounds.center(), 0.5 * glm::length(bounds.size()),
                                  Orbit{options.direction[0], options.direction[1], distance}, options.width,
                                  options.height));
  const std::vector<ModeFrames> rendered = modes.render(cameras, [&](std::size_t done, std::size_t total) {
    meter.update(double(done) / double(total), "frame " + std::to_string(done) + "/" + std::to_string(total));
  });
  for (std::size_t v = 0; v < kViewNames.size(); ++v) {
    const ModeFrames& frames = rendered[v];
    tiles.push_back(toRgba8(frames.exact.image));
    tiles.push_back(toRgba8(frames.surfels.image));
    tiles.push_back(differenceRgba8(frames.surfels.image, frames.exact.image, kDifferenceGain));
    rows.push_back({.name = kViewNames[v],
                    .distance = options.distances[v],
                    .exactMs = frames.exact.seconds * 1e3,
                    .surfelsMs = frames.surfels.seconds * 1e3,
                    .surfelsStats = frames.surfels.stats,
                    .exactTriangles = frames.exact.stats.triangles,
                    .error = frames.error});
  }
  meter.finish(std::to_string(kViewNames.size()) + " views in each mode");

  const std::vector<std::span<const std::uint8_t>> spans(tiles.begin(), tiles.end());
  const std::uint8_t background[3] = {235, 235, 235};
  writeImage8(folder / "views.png", 3 * options.width, std::uint32_t(rows.size()) * options.height, 3,
              contactSheet(options.width, options.height, 3, spans, background));
  writeTextFile(folder / "views.csv", viewsCsv(rows));
  writeTextFile(folder / "views.json", viewsJson(options, loaded.name, rows).dump(2) + "\n");

  std::printf("%s: %ux%u, azimuth %.0f°, elevation %.0f°\n", loaded.name.c_str(), options.width, options.height,
              options.direction[0], options.direction[1]);
  std::printf("%-7s %8s %10s %10s %12s %12s %12s %7s %7s %9s\n", "view", "radii", "exact ms", "surfels ms", "surfels",
              "triangles", "exact tri.", "PSNR", "SSIM", "holes");
  for (const ViewRow& r : rows)
    std::printf("%-7s %8.2f %10.1f %10.1f %12s %12s %12s %7.2f %7.4f %9.2e\n", r.name, r.distance, r.exactMs,
                r.surfelsMs, withThousands(r.surfelsStats.surfels).c_str(),
                withThousands(r.surfelsStats.triangles).c_str(), withThousands(r.exactTriangles).c_str(), r.error.psnr,
                r.error.ssim, r.error.holeFraction);
  std::printf("wrote %s/{views.png, views.csv, views.json}\n", folder.string().c_str());
}

}  // namespace pbs::cli
