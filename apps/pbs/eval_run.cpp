// runEval: one FrameRenderer per setting, reused over the orbit so its timings match `pbs render`.
#include "eval_run.hpp"

#include "frame_renderer.hpp"

#include <pbs/raster/headlight_shading.hpp>

#include <stdexcept>

namespace pbs::cli {

EvalResults runEval(const Scene& scene, const Hierarchy& hierarchy, const std::vector<OrbitView>& views,
                    const std::vector<EvalSetting>& settings,
                    const std::function<const SceneSurfels&(const EvalSetting&)>& surfelsOf,
                    const std::function<const Scene&(const EvalSetting&)>& simplifiedOf,
                    const std::function<void(std::size_t, std::size_t, const std::string&)>& onProgress) {
  if (views.empty()) throw std::invalid_argument("runEval: no views");
  const std::uint32_t width = views.front().camera.width, height = views.front().camera.height;
  const std::size_t total = views.size() * (1 + settings.size());
  std::size_t done = 0;
  const auto progress = [&](const std::string& name, std::size_t f) {
    ++done;
    if (onProgress) onProgress(done, total, name + ", frame " + std::to_string(f + 1) + "/" + std::to_string(views.size()));
  };

  EvalResults results;
  std::vector<RgbaImage> reference;
  {
    FrameRenderer renderer(scene, hierarchy, RenderMode::Exact, nullptr, LodOptions{}, width, height);
    for (std::size_t f = 0; f < views.size(); ++f) {
      FrameResult frame = renderer.render(views[f].camera);
      results.reference.push_back(
          {.frame = std::uint32_t(f), .azimuthDegrees = views[f].azimuthDegrees, .seconds = frame.seconds,
           .stats = frame.stats, .error = {}});
      if (f == 0) results.referenceFirst = toRgba8(frame.image);
      reference.push_back(RgbaImage{width, height, std::move(frame.image)});
      progress("exact reference", f);
    }
  }
  for (const EvalSetting& setting : settings) {
    const SceneSurfels* surfels = setting.exact ? nullptr : &surfelsOf(setting);
    const Scene* simplified = setting.simplify ? &simplifiedOf(setting) : nullptr;
    const RenderMode mode = setting.exact ? RenderMode::Exact : simplified ? RenderMode::Simplified : RenderMode::Surfels;
    FrameRenderer renderer(scene, hierarchy, mode, surfels, setting.lod, width, height, simplified);
    EvalSettingResult result;
    for (std::size_t f = 0; f < views.size(); ++f) {
      FrameResult frame = renderer.render(views[f].camera);
      if (f == 0) {
        result.firstImage = toRgba8(frame.image);
        result.firstDifference = differenceRgba8(frame.image, reference[f].pixels, kDifferenceGain);
      }
      const RgbaImage image{width, height, std::move(frame.image)};
      result.frames.push_back({.frame = std::uint32_t(f), .azimuthDegrees = views[f].azimuthDegrees,
                               .seconds = frame.seconds, .stats = frame.stats,
                               .error = compareImages(image, reference[f])});
      progress(setting.name, f);
    }
    results.settings.push_back(std::move(result));
  }
  return results;
}

}  // namespace pbs::cli
