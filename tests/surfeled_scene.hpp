// A scene with surfels from surfelize at small, fast settings, for tests that render it.
#pragma once

#include <pbs/scene/hierarchy.hpp>
#include <pbs/scene/scene.hpp>
#include <pbs/surfels/scene_surfels.hpp>
#include <pbs/surfels/surfelize.hpp>

#include <cstdint>
#include <utility>

namespace pbs::test {

struct SurfeledScene {
  Scene scene;
  Hierarchy hierarchy;
  SceneSurfels surfels;
};

// Arrays for nodes above `threshold` triangles, 4000 surfels each, captured at 128 pixels.
inline SurfeledScene surfeled(Scene scene, std::uint64_t threshold = 1000) {
  SurfeledScene s{std::move(scene), {}, {}};
  s.hierarchy = analyzeHierarchy(s.scene);
  SurfelizeOptions options;
  options.file.threshold = threshold;
  options.file.maxSurfels = 4000;
  options.file.resolution = 128;
  s.surfels = sceneSurfelsOf(surfelize(s.scene, s.hierarchy, options), s.scene, s.hierarchy, "test");
  return s;
}

}  // namespace pbs::test
