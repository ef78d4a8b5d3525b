// calibrateFrameCosts: frames timed under cuts from coarse to fine, and the costs fitted to them.
#include "pbs/evaluation/frame_calibration.hpp"
#include "pbs/evaluation/view_draws.hpp"

#include <pbs/raster/image_upscale.hpp>
#include <pbs/scene/input_error.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <string_view>

namespace pbs {
namespace {

// The file's names for the costs, in FrameCosts' order.
struct CostField {
  const char* name;
  double FrameCosts::*cost;
};
constexpr CostField kCostFields[] = {{"image_pixel", &FrameCosts::perImagePixel},
                                     {"raster_triangle", &FrameCosts::rasterPerTriangle},
                                     {"raster_pixel", &FrameCosts::rasterPerPixel},
                                     {"raster_box_pixel", &FrameCosts::rasterPerBoxPixel},
                                     {"raster_node", &FrameCosts::rasterPerNode},
                                     {"raster_triangle_on_pixels", &FrameCosts::rasterPerTriangleOnPixels},
                                     {"rays_image_pixel", &FrameCosts::raysPerImagePixel},
                                     {"rays_pixel", &FrameCosts::raysPerPixel},
                                     {"rays_box_pixel", &FrameCosts::raysPerBoxPixel},
                                     {"rays_node", &FrameCosts::raysPerNode},
                                     {"surfel", &FrameCosts::perSurfel},
                                     {"surfel_pixel", &FrameCosts::perSurfelPixel},
                                     {"node", &FrameCosts::perNode},
                                     {"node_weighed", &FrameCosts::perNodeWeighed},
                                     {"upscale_pixel", &FrameCosts::upscalePerPixel}};
// Version 2 added these; a version 1 file is still read, with their defaults.
constexpr int kFileVersion = 2;
constexpr std::string_view kAddedInVersion2[] = {"raster_triangle_on_pixels", "node_weighed", "upscale_pixel"};

// The middle value of a timing's runs, the upper of the two middle ones for an even count (as the repeats of a
// calibration frame count the slower of two); `values` not empty.
double upperMedian(std::vector<double> values) {
  const auto middle = values.begin() + std::ptrdiff_t(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// Seconds per output pixel of bringing a third-size frame up to width × height (the budget's most common
// divisor; the pass's work is mostly per output pixel), the median of `runs`. The image's content
// does not matter: the pass has no branch on it.
double timeUpscalePerPixel(std::uint32_t width, std::uint32_t height, std::uint32_t runs) {
  const std::uint32_t w = std::max(1u, width / 3), h = std::max(1u, height / 3);
  std::vector<glm::vec4> image(std::size_t(w) * h);
  for (std::size_t i = 0; i < image.size(); ++i)
    image[i] = i % 3 ? glm::vec4(0.5f, 0.25f, 0.75f, 1.0f) : glm::vec4(0.0f);
  std::vector<double> seconds;
  for (std::uint32_t r = 0; r < runs; ++r) {
    const auto start = std::chrono::steady_clock::now();
    const std::vector<std::uint8_t> bytes = upscaleBilinearRgba8(image, w, h, width, height);
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return upperMedian(std::move(seconds)) / (double(width) * double(height));
}

// Seconds per node a budget's traversal weighs (FrameWork::nodesWeighed): each camera's cut chosen for 33 ms by
// `costs`, the median over the cameras of its traversal's time per node weighed.
double timeNodeWeighing(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels,
                        std::span<const Camera> cameras, LodOptions lod, const FrameCosts& costs) {
  lod.budget = LodBudget::seconds(0.033);
  lod.frameCosts = costs;
  std::vector<double> perNode;
  for (const Camera& camera : cameras) {
    const auto start = std::chrono::steady_clock::now();
    const LodDraws draws = traverseLod(scene, hierarchy, surfels, camera, lod);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (draws.nodesWeighed > 0) perNode.push_back(seconds / double(draws.nodesWeighed));
  }
  return perNode.empty() ? costs.perNodeWeighed : upperMedian(std::move(perNode));
}

// The smallest size on screen a calibration's budget cuts descend from.
constexpr double kCalibrationThresholdPixels = 1.0;

}  // namespace

std::vector<CalibrationCut> calibrationCuts(const LodOptions& base) {
  std::vector<std::pair<std::string, LodOptions>> cuts;
  for (double threshold : {32.0, 128.0}) {
    LodOptions lod = base;
    lod.budget = {};
    lod.threshold = threshold;
    cuts.emplace_back("threshold=" + std::to_string(int(threshold)), lod);
  }
  for (double primitives : {250e3, 1e6, 4e6, 16e6}) {
    LodOptions lod = base;
    lod.budget = LodBudget::primitives(primitives);
    // Refining below any threshold, so the cuts reach from the coarsest to mostly triangles: the fit needs
    // frames of every mix, though a budget itself stops at the threshold.
    lod.threshold = kCalibrationThresholdPixels;
    cuts.emplace_back("primitives=" + std::to_string(std::uint64_t(primitives)), lod);
  }
  std::vector<CalibrationCut> drawn;
  for (GeometryDrawer drawer : {GeometryDrawer::Raster, GeometryDrawer::Rays}) {
    for (auto [name, lod] : cuts) {
      lod.geometry = drawer;
      drawn.push_back({name + "+geometry=" + geometryDrawerName(drawer), lod});
    }
  }
  return drawn;
}

FrameCalibration calibrateFrameCosts(const Scene& scene, const Hierarchy& hierarchy, const FrameSources& sources,
                                     std::span<const Camera> cameras, std::span<const CalibrationCut> cuts,
                                     std::uint32_t repeats, double quantile, const ProgressEvents& progress) {
  FrameCalibration calibration;
  if (cameras.empty()) return calibration;
  const std::string step = "timing frames";
  progress.begun(step);
  const std::size_t total = cuts.size() * cameras.size();
  std::vector<TimedFrame> timed;
  for (std::size_t c = 0; c < cuts.size(); ++c) {
    FrameRenderer renderer(scene, hierarchy, {.mode = RenderMode::Surfels, .lod = cuts[c].lod}, cameras[0].width,
                           cameras[0].height, sources);
    for (std::uint32_t v = 0; v < cameras.size(); ++v) {
      // The repeat of median time (the slower of two): a budgeted frame is drawn once, and takes what a frame
      // typically takes, not the least it can.
      const ViewDraws draws = drawView(renderer, cameras[v], int(std::max(repeats, 1u)),
                                       [](const FrameResult& result) { return result.recurringSeconds(); });
      const FrameResult& median = draws.byTime[draws.byTime.size() / 2];
      const TimedFrame timedMedian{.work = frameWork(median.stats, std::uint64_t(cameras[v].width) * cameras[v].height),
                                   .seconds = median.recurringSeconds(),
                                   .geometrySeconds = median.stats.geometrySeconds - median.stats.bvhBuildSeconds,
                                   .drawer = median.stats.geometryDrawer};
      CalibrationFrame frame{.cut = cuts[c].name, .view = v, .timed = timedMedian};
      // The clock's resolution: no frame takes no time.
      frame.timed.seconds = std::max(frame.timed.seconds, 1e-6);
      frame.timed.geometrySeconds = std::clamp(frame.timed.geometrySeconds, 0.0, 0.99 * frame.timed.seconds);
      timed.push_back(frame.timed);
      calibration.frames.push_back(frame);
      const std::size_t done = c * cameras.size() + v + 1;
      progress.updated(step, double(done) / double(total),
                       std::to_string(done) + " of " + std::to_string(total) + " frames");
    }
  }
  calibration.fit = fitFrameCosts(timed, quantile);
  const SceneSurfels& surfels = sources.surfels ? *sources.surfels : sources.cache->surfels();
  calibration.fit.costs.perNodeWeighed =
      timeNodeWeighing(scene, hierarchy, surfels, cameras, cuts.front().lod, calibration.fit.costs);
  calibration.fit.costs.upscalePerPixel =
      timeUpscalePerPixel(cameras[0].width, cameras[0].height, 4 * std::max(repeats, 1u) + 1);
  progress.ended(step, std::to_string(total) + " frames");
  return calibration;
}

nlohmann::json calibrationJson(const FrameCalibration& calibration) {
  nlohmann::json json = {{"pbs_frame_costs", kFileVersion}};
  for (const CostField& field : kCostFields) json["seconds_per"][field.name] = calibration.fit.costs.*field.cost;
  json["fit"] = {{"frames", calibration.fit.frames},
                 {"raster_frames", calibration.fit.rasterFrames},
                 {"ray_frames", calibration.fit.rayFrames},
                 {"quantile", calibration.fit.quantile},
                 {"scale", calibration.fit.scale},
                 {"median_relative_error", calibration.fit.medianError},
                 {"p90_relative_error", calibration.fit.p90Error}};
  for (const CalibrationFrame& frame : calibration.frames) {
    const TimedFrame& t = frame.timed;
    json["frames"].push_back({{"cut", frame.cut},
                              {"view", frame.view},
                              {"seconds", t.seconds},
                              {"geometry_seconds", t.geometrySeconds},
                              {"geometry_drawer", geometryDrawerName(t.drawer)},
                              {"predicted_seconds", predictFrameCost(calibration.fit.costs, t.work, t.drawer)},
                              {"image_pixels", t.work.imagePixels},
                              {"triangles", t.work.triangles},
                              {"geometry_pixels", t.work.geometryPixels},
                              {"geometry_ray_pixels", t.work.geometryRayPixels},
                              {"triangles_on_pixels", t.work.trianglesOnPixels},
                              {"surfels", t.work.surfels},
                              {"surfel_pixels", t.work.surfelPixels},
                              {"nodes", t.work.nodes},
                              {"geometry_nodes", t.work.geometryNodes}});
  }
  return json;
}

FrameCosts frameCostsFromJson(const nlohmann::json& json, std::string_view file) {
  if (!json.is_object() || !json.contains("pbs_frame_costs"))
    throw InputError(file, "", "not a calibration file (no pbs_frame_costs; make one with pbs calibrate)");
  const nlohmann::json& version = json["pbs_frame_costs"];
  if (version != 1 && version != kFileVersion)
    throw InputError(file, "pbs_frame_costs", "version " + version.dump() + ", this pbs reads 1 and 2");
  const nlohmann::json* per = json.contains("seconds_per") ? &json["seconds_per"] : nullptr;
  if (!per || !per->is_object()) throw InputError(file, "seconds_per", "missing");
  FrameCosts costs;
  for (const CostField& field : kCostFields) {
    if (version == 1 && std::ranges::find(kAddedInVersion2, std::string_view(field.name)) != std::end(kAddedInVersion2))
      continue;
    const std::string element = std::string("seconds_per.") + field.name;
    if (!per->contains(field.name)) throw InputError(file, element, "missing");
    const nlohmann::json& value = (*per)[field.name];
    if (!value.is_number() || !std::isfinite(value.get<double>()) || value.get<double>() < 0.0 ||
        value.get<double>() > 1.0)
      throw InputError(file, element, "expected seconds in [0, 1], got " + value.dump());
    costs.*field.cost = value.get<double>();
  }
  return costs;
}

}  // namespace pbs
