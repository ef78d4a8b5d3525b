// EvalSurfelSources and EvalSimplifiedScenes: made once per ordering and per ratio, timed apart.
#include "pbs/evaluation/eval_sources.hpp"

#include "pbs/evaluation/mode_comparison.hpp"
#include "pbs/evaluation/report_numbers.hpp"

#include <algorithm>
#include <chrono>
#include <string>
#include <utility>

namespace pbs {

EvalSurfelSources::EvalSurfelSources(const Scene& scene, const Hierarchy& hierarchy, SurfelFileReader reader,
                                     std::uint64_t cacheBytes, CaptureSource source, ProgressEvents progress)
    : scene_(scene),
      hierarchy_(hierarchy),
      source_(source),
      progress_(std::move(progress)),
      cache_(std::move(reader), scene, hierarchy, cacheBytes) {}

FrameSources EvalSurfelSources::of(const EvalSetting& setting) {
  const SurfelFileOptions& options = cache_.options();
  if (!setting.ordering || *setting.ordering == options.ordering) return {.cache = &cache_};
  auto found = made_.find(*setting.ordering);
  if (found != made_.end()) return {.surfels = &found->second};
  SurfelizeOptions settings;
  settings.file = options;
  settings.file.ordering = *setting.ordering;
  settings.source = source_;
  const std::string name(orderingName(*setting.ordering));
  MadeSurfels made = surfelizeInMemory(scene_, hierarchy_, settings, "surfelize " + name, progress_);
  const SceneSurfels& kept = made_.emplace(*setting.ordering, std::move(made.surfels)).first->second;
  return {.surfels = &kept};
}

const Scene& EvalSimplifiedScenes::of(const EvalSetting& setting) {
  const double ratio = *setting.simplify;
  auto found = made_.find(ratio);
  if (found != made_.end()) return found->second.simplified.scene;
  progress_.begun(setting.name);
  SimplifyOptions options;
  options.ratio = ratio;
  const auto start = std::chrono::steady_clock::now();
  Made made{simplifyScene(scene_, options), 0.0};
  made.seconds = secondsSince(start);
  progress_.ended(setting.name, withThousands(made.simplified.trianglesBefore) + " → " +
                                    withThousands(made.simplified.trianglesAfter) + " mesh triangles");
  return made_.emplace(ratio, std::move(made)).first->second.simplified.scene;
}

nlohmann::json EvalSimplifiedScenes::json() const {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& [ratio, made] : made_) {
    const SimplifiedScene& s = made.simplified;
    list.push_back(
        {{"ratio", ratio},
         {"seconds", made.seconds},
         {"mesh_triangles_before", s.trianglesBefore},
         {"mesh_triangles_after", s.trianglesAfter},
         {"kept_fraction", s.trianglesBefore > 0 ? double(s.trianglesAfter) / double(s.trianglesBefore) : 1.0},
         {"largest_error", s.largestError},
         {"target_error", SimplifyOptions{}.targetError}});
  }
  return list;
}

}  // namespace pbs
