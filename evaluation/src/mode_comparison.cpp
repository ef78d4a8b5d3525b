// surfelizeInMemory and ModeComparison: the measuring the figures and the evaluation share.
#include "pbs/evaluation/mode_comparison.hpp"

#include "pbs/evaluation/report_numbers.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace pbs {

MadeSurfels surfelizeInMemory(const Scene& scene, const Hierarchy& hierarchy, const SurfelizeOptions& options,
                              const std::string& label, const ProgressEvents& progress) {
  progress.begun(label);
  SurfelizeOptions settings = options;
  settings.onProgress = [&](const SurfelizeProgress& p) {
    progress.updated(label, double(p.arraysDone) / double(std::max(p.arraysTotal, 1u)),
                     std::to_string(p.arraysDone) + "/" + std::to_string(p.arraysTotal) + " arrays");
  };
  MadeSurfels made;
  const auto start = std::chrono::steady_clock::now();
  const SurfelFile file = surfelize(scene, hierarchy, settings, &made.stats);
  made.seconds = secondsSince(start);
  if (made.stats.arrays > 0)
    progress.ended(label,
                   std::to_string(made.stats.arrays) + " arrays, " + withThousands(made.stats.surfels) + " surfels");
  made.surfels = sceneSurfelsOf(file, scene, hierarchy, label);
  return made;
}

ModeComparison::ModeComparison(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels,
                               const LodOptions& lod, std::uint32_t width, std::uint32_t height)
    : width_(width),
      height_(height),
      exact_(scene, hierarchy, {.mode = RenderMode::Exact, .lod = lod}, width, height),
      surfels_(scene, hierarchy, {.mode = RenderMode::Surfels, .lod = lod}, width, height, {.surfels = &surfels}) {}

std::vector<ModeFrames> ModeComparison::render(std::span<const Camera> cameras,
                                               const std::function<void(std::size_t, std::size_t)>& onFrame) {
  std::vector<ModeFrames> frames(cameras.size());
  const std::size_t total = 2 * cameras.size();
  for (std::size_t v = 0; v < cameras.size(); ++v) {
    frames[v].exact = exact_.render(cameras[v]);
    onFrame(v + 1, total);
  }
  for (std::size_t v = 0; v < cameras.size(); ++v) {
    frames[v].surfels = surfels_.render(cameras[v]);
    // compareImages takes whole images; the copies cost far less than the frames themselves.
    frames[v].error = compareImages(RgbaImage{width_, height_, frames[v].surfels.image},
                                    RgbaImage{width_, height_, frames[v].exact.image});
    onFrame(cameras.size() + v + 1, total);
  }
  return frames;
}

}  // namespace pbs
