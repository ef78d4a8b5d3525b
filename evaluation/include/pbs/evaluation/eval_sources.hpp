// What the settings of an evaluation draw besides the peers: the surfel file's own arrays (read as frames
// draw them, one cache for every setting), arrays of other orderings made on demand with the file's
// options, and simplified copies of the scene. Each is made once, before the frames are timed.
#pragma once

#include "pbs/evaluation/eval_settings.hpp"
#include "pbs/evaluation/progress_events.hpp"

#include <pbs/scene/hierarchy.hpp>
#include <pbs/scene/scene.hpp>
#include <pbs/scene/simplified_meshes.hpp>
#include <pbs/surfels/frame_renderer.hpp>
#include <pbs/surfels/scene_surfels.hpp>
#include <pbs/surfels/surfel_cache.hpp>
#include <pbs/surfels/surfel_file.hpp>
#include <pbs/surfels/surfelize.hpp>

#include <nlohmann/json.hpp>

#include <cstdint>
#include <map>

namespace pbs {

class EvalSurfelSources {
 public:
  // `reader` must have been required for the scene (hierarchyWithSurfels or requireStructure).
  EvalSurfelSources(const Scene& scene, const Hierarchy& hierarchy, SurfelFileReader reader, std::uint64_t cacheBytes,
                    CaptureSource source, ProgressEvents progress = {});

  SurfelOrdering fileOrdering() const { return cache_.options().ordering; }
  // The arrays' lengths and packing, which decide the traversal (each view's kind among it).
  const SceneSurfels& decisions() const { return cache_.surfels(); }
  // What was read of the file: its tables, and the chunks the frames drew.
  std::uint64_t bytesRead() const { return cache_.tablesBytes() + cache_.stats().bytesRead; }

  // The arrays `setting` draws: the file's (through the cache), or those of its ordering, made the first
  // time they are asked for (reported as step "surfelize ORDERING").
  FrameSources of(const EvalSetting& setting);

 private:
  const Scene& scene_;
  const Hierarchy& hierarchy_;
  CaptureSource source_;
  ProgressEvents progress_;
  SurfelCache cache_;
  std::map<SurfelOrdering, SceneSurfels> made_;
};

// Simplified copies of the scene, one per ratio a sweep names.
class EvalSimplifiedScenes {
 public:
  explicit EvalSimplifiedScenes(const Scene& scene, ProgressEvents progress = {})
      : scene_(scene), progress_(std::move(progress)) {}

  // The scene simplified to `setting.simplify` (set), made the first time it is asked for (reported as
  // a step named after the setting).
  const Scene& of(const EvalSetting& setting);

  // Per ratio: its time, the meshes' triangles (each mesh once) before and after, the largest relative
  // deformation reached and the error bound simplification stopped at.
  nlohmann::json json() const;

 private:
  struct Made {
    SimplifiedScene simplified;
    double seconds = 0.0;
  };
  const Scene& scene_;
  ProgressEvents progress_;
  std::map<double, Made> made_;
};

}  // namespace pbs
