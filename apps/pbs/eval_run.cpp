// runEval: one FrameRenderer per setting, reused over the orbit so its timings match `pbs render`.
#include "eval_run.hpp"

#include "frame_renderer.hpp"

#include <pbs/raster/headlight_shading.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pbs::cli {

std::vector<std::uint8_t> differenceRgba8(const std::vector<glm::vec4>& a, const std::vector<glm::vec4>& b,
                                          float gain) {
  if (a.size() != b.size()) throw std::invalid_argument("differenceRgba8: images differ in size");
  std::vector<std::uint8_t> out(a.size() * 4);
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const float d = std::clamp(std::abs(a[i][c] - b[i][c]) * gain, 0.0f, 1.0f);
      out[4 * i + std::size_t(c)] = std::uint8_t(std::lround(d * 255.0f));
    }
    out[4 * i + 3] = 255;
  }
  return out;
}

EvalResults runEval(const Scene& scene, const Hierarchy& hierarchy, const std::vector<OrbitView>& views,
                    const std::vector<EvalSetting>& settings,
                    const std::function<const SceneSurfels&(const EvalSetting&)>& surfelsOf,
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
    FrameRenderer renderer(scene, hierarchy, setting.exact ? RenderMode::Exact : RenderMode::Surfels, surfels,
                           setting.lod, width, height);
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
