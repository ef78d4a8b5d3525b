// runEval: one Embree BVH for the reference and the Embree peers (where they cast rays), one FrameRenderer
// per setting reused over the path so its timings match `pbs render`.
#include "pbs/evaluation/eval_run.hpp"

#include "pbs/evaluation/report_numbers.hpp"
#include "pbs/evaluation/view_draws.hpp"

#include <pbs/raster/flip.hpp>
#include <pbs/raster/headlight_shading.hpp>
#include <pbs/scene/embree_caster.hpp>
#include <pbs/surfels/frame_renderer.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

namespace pbs {
namespace {

double coveredPixels(const std::vector<glm::vec4>& image) {
  double covered = 0.0;
  for (const glm::vec4& p : image) covered += p.a > 0.0f;
  return covered;
}

// Per frame, the fastest 1-sample peer's time over each setting's.
void setSpeedups(const std::vector<EvalSetting>& settings, std::vector<EvalSettingResult>& results) {
  if (results.empty()) return;
  const std::size_t frames = results.front().frames.size();
  for (std::size_t f = 0; f < frames; ++f) {
    double fastest = std::numeric_limits<double>::infinity();
    for (std::size_t s = 0; s < settings.size(); ++s)
      if (settings[s].isPeer() && settings[s].samples == 1) fastest = std::min(fastest, results[s].frames[f].seconds);
    if (!std::isfinite(fastest)) return;
    for (EvalSettingResult& result : results)
      if (result.frames[f].seconds > 0.0) result.frames[f].speedupOverFastestExact = fastest / result.frames[f].seconds;
  }
}

}  // namespace

bool castsRaysOverWholeScene(const std::vector<EvalSetting>& settings, RenderMode reference) {
  return reference == RenderMode::Embree || std::any_of(settings.begin(), settings.end(), [](const EvalSetting& s) {
           return s.mode == RenderMode::Embree;
         });
}

bool drawableWithMeshesOnDemand(const std::vector<EvalSetting>& settings, RenderMode reference,
                                SurfelOrdering fileOrdering) {
  return !castsRaysOverWholeScene(settings, reference) &&
         std::none_of(settings.begin(), settings.end(),
                      [&](const EvalSetting& s) { return s.simplify || (s.ordering && *s.ordering != fileOrdering); });
}

EvalResults runEval(const Scene& scene, const Hierarchy& hierarchy, const std::vector<Camera>& cameras,
                    const std::vector<EvalSetting>& settings, const EvalInputs& inputs,
                    const std::function<FrameSources(const EvalSetting&)>& surfelsOf,
                    const std::function<const Scene&(const EvalSetting&)>& simplifiedOf,
                    const std::function<void(std::size_t, std::size_t, const std::string&)>& onProgress) {
  if (cameras.empty()) throw std::invalid_argument("runEval: no views");
  const std::uint32_t width = cameras.front().width, height = cameras.front().height;
  const std::size_t total = cameras.size() * (1 + settings.size());
  std::size_t done = 0;
  const auto progress = [&](const std::string& name, std::size_t f) {
    ++done;
    if (onProgress)
      onProgress(done, total, name + ", frame " + std::to_string(f + 1) + "/" + std::to_string(cameras.size()));
  };

  EvalResults results;
  // One BVH over the whole scene, where the reference or a peer casts rays over it.
  const bool wholeRays = castsRaysOverWholeScene(settings, inputs.referenceMode);
  if (wholeRays && inputs.meshes)
    throw std::invalid_argument("runEval: Embree over a scene whose meshes are read on demand");
  std::optional<EmbreeScene> rays;
  if (wholeRays) {
    const auto build = std::chrono::steady_clock::now();
    rays.emplace(scene, hierarchy);
    results.buildSeconds = secondsSince(build);
  }
  const EmbreeScene* sharedRays = rays ? &*rays : nullptr;

  // A frame's kind says how near the view is under the one threshold: an option that descends sooner
  // (descendExhausted, descendWhereRaysCheaper) must not move its own frames to the near kind's laxer targets.
  LodOptions kindLod = inputs.kindLod;
  kindLod.descendExhausted = false;
  kindLod.descendWhereRaysCheaper = false;
  std::vector<RgbaImage> reference;
  {
    FrameRenderer renderer(
        scene, hierarchy, {.mode = inputs.referenceMode, .lod = {}, .samples = inputs.referenceSamples}, width, height,
        {.meshes = inputs.referenceMode == RenderMode::Exact ? inputs.meshes : nullptr, .rays = sharedRays});
    for (std::size_t f = 0; f < cameras.size(); ++f) {
      FrameResult frame = renderer.render(cameras[f]);
      EvalView view{.camera = cameras[f], .referenceSeconds = frame.seconds};
      if (inputs.kindSurfels) {
        const double covered = coveredPixels(frame.image);
        const auto geometry = double(geometryPixels(scene, hierarchy, *inputs.kindSurfels, cameras[f], kindLod));
        view.geometryShare = covered > 0.0 ? std::min(1.0, geometry / covered) : 0.0;
        view.kind = frameKindOf(view.geometryShare);
      }
      results.views.push_back(view);
      if (f == inputs.sheetFrame) results.referenceSheet = toRgba8(frame.image);
      reference.push_back(RgbaImage{width, height, std::move(frame.image)});
      progress("reference", f);
    }
  }
  for (const EvalSetting& setting : settings) {
    FrameSources sources = setting.isPeer() ? FrameSources{} : surfelsOf(setting);
    sources.simplified = setting.simplify ? &simplifiedOf(setting) : nullptr;
    sources.rays = sharedRays;
    if (setting.mode == RenderMode::Exact || sources.cache) sources.meshes = inputs.meshes;
    // The path's frames share the mesh BVHs that rays build, as in `pbs render --frames`: each frame is
    // charged its share of a build, whether the peers' BVH already holds it or not.
    LodOptions lod = setting.lod;
    lod.bvhBuildFrames = double(cameras.size());
    FrameRenderer renderer(scene, hierarchy,
                           {.mode = setting.mode, .lod = lod, .samples = setting.samples, .textures = inputs.textures},
                           width, height, sources);
    EvalSettingResult result;
    for (std::size_t f = 0; f < cameras.size(); ++f) {
      // Reading the file is reported apart (the first setting to draw a prefix would pay for all), and so
      // are the first draw's BVH builds, which the median draw leaves out.
      ViewDraws draws = drawView(renderer, cameras[f], inputs.draws,
                                 [](const FrameResult& drawn) { return drawn.seconds - drawn.surfelLoadSeconds; });
      const FrameResult& frame = draws.first;
      const FrameResult& median = draws.byTime[(draws.byTime.size() - 1) / 2];
      const RgbaImage image{width, height, std::move(draws.first.image)};
      CompareOptions compare = inputs.compare;
      compare.keepFlipMap = f == inputs.sheetFrame;
      ImageDifference error = compareImages(image, reference[f], compare);
      if (f == inputs.sheetFrame) {
        result.sheetImage = toRgba8(image.pixels);
        result.sheetFlip = flipMapRgba8(error.flipMap);
        error.flipMap = {};
      }
      result.frames.push_back({.frame = std::uint32_t(f),
                               .seconds = median.seconds - median.surfelLoadSeconds,
                               .surfelLoadSeconds = frame.surfelLoadSeconds,
                               .bvhBuildSeconds = frame.stats.bvhBuildSeconds,
                               .divisor = frame.divisor,
                               .stats = median.stats,
                               .error = std::move(error),
                               .speedupOverFastestExact = 0.0});
      progress(setting.name, f);
    }
    results.settings.push_back(std::move(result));
  }
  setSpeedups(settings, results.settings);
  return results;
}

}  // namespace pbs
