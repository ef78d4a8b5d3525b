// The capture sweep over triangle sizes: one sized terrain at a time (only one is in memory), each
// timed by the same measurement as a single scene.
#include "raster_sweep.hpp"

#include "sized_terrain.hpp"
#include "timing.hpp"

#include <pbs/raster/box_view.hpp>
#include <pbs/raster/thread_arena.hpp>

#include <string>

namespace pbs::bench {
namespace {

// The contenders of benchCapture's report, as keys and as legend names.
struct Contender {
  const char* key;
  const char* name;
};
constexpr Contender kContenders[] = {
    {"pbs", "pbs"}, {"pbs_1_thread", "pbs, 1 thread"}, {"embree", "Embree packets"}, {"llvmpipe", "llvmpipe"}};

// Million triangles drawn per second by each contender (null for a missing one).
nlohmann::json throughputs(const nlohmann::json& capture, double drawnTriangles) {
  nlohmann::json out;
  for (const Contender& contender : kContenders) {
    const nlohmann::json& entry = capture[contender.key];
    out[contender.key] =
        entry.contains("seconds") ? nlohmann::json(drawnTriangles / entry["seconds"].get<double>() / 1e6) : nullptr;
  }
  return out;
}

}  // namespace

nlohmann::json benchRasterSweep(const RasterSweepOptions& options) {
  const std::size_t views = boxCornerDirections().size();
  nlohmann::json sizes = nlohmann::json::array();
  for (const double asked : options.pixelsPerTriangle) {
    const SizedTerrain terrain = sizedTerrain(asked, options.raster.resolution);
    const std::uint64_t triangles = terrain.scene.meshes.front().triangleCount();
    nlohmann::json capture = benchCapture(terrain.scene, terrain.hierarchy, options.raster);
    sizes.push_back({{"pixels_per_triangle_asked", asked},
                     {"pixels_per_triangle", terrain.pixelsPerTriangle},
                     {"triangles", triangles},
                     {"mtriangles_per_s", throughputs(capture, double(triangles) * double(views))},
                     {"capture", std::move(capture)}});
  }
  return {{"mesh", "terrain (pbs generate terrain), tessellated for each size"},
          {"sizes", std::move(sizes)},
          {"views", views},
          {"threads", resolveThreadCount(options.raster.threads)},
          {"resolution", options.raster.resolution},
          {"repeats", options.raster.repeats},
          {"timing", kInterleavedTiming}};
}

Plot rasterSweepPlot(const nlohmann::json& report) {
  Plot plot;
  plot.title = "capture of " + std::to_string(report["views"].get<int>()) + " views at " +
               std::to_string(report["resolution"].get<int>()) + " px, " +
               std::to_string(report["threads"].get<int>()) + " threads: throughput against triangle size";
  plot.x = {.label = "pixels per triangle (mean projected area)", .log = true, .min = {}, .max = {}};
  plot.y = {.label = "million triangles drawn per second", .log = true, .min = {}, .max = {}};
  for (const Contender& contender : kContenders) {
    PlotSeries series{.name = contender.name, .points = {}, .color = {}};
    for (const nlohmann::json& size : report["sizes"]) {
      const nlohmann::json& throughput = size["mtriangles_per_s"][contender.key];
      if (!throughput.is_null())
        series.points.emplace_back(size["pixels_per_triangle"].get<double>(), throughput.get<double>());
    }
    if (!series.points.empty()) plot.series.push_back(std::move(series));
  }
  return plot;
}

}  // namespace pbs::bench
